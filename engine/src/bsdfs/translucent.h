// Translucent BSDF: Lambertian transmission, f = color / pi on the far side.
#pragma once
#include "bsdfs/bsdf.h"

namespace rdv::translucent {
Color eval(const Lobe &lobe, Vec3 wo, Vec3 wi);
float pdf(const Lobe &lobe, Vec3 wo, Vec3 wi);
bool sample(const Lobe &lobe, Vec3 wo, Vec2 u, Vec3 &wi, Color &weight, float &pdf);
}  // namespace rdv::translucent
