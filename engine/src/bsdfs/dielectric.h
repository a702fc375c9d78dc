// Dielectric interface (glass, water): smooth (delta) and rough GGX reflection +
// refraction (Walter et al. 2007, with visible-normal sampling, Heitz 2018).
#pragma once
#include "bsdfs/bsdf.h"

namespace rdv::dielectric {
Color eval(const Lobe &lobe, Vec3 wo, Vec3 wi, TransportMode mode);
float pdf(const Lobe &lobe, Vec3 wo, Vec3 wi);
bool sample(const Lobe &lobe, Vec3 wo, Vec2 u, float uc, Vec3 &wi, Color &weight, float &pdf, TransportMode mode);
bool sample_smooth(const Lobe &lobe, Vec3 wo, Vec2 u, Vec3 &wi, Color &weight, float &pdf, TransportMode mode);
}  // namespace rdv::dielectric
