// Transparent BSDF (and the alpha of a Principled BSDF): light passes straight
// through, tinted by color. A delta lobe; no refraction, so no eta^2 scaling.
#pragma once
#include "bsdfs/bsdf.h"

namespace rdv::transparent {
bool sample(const Lobe &lobe, Vec3 wo, Vec3 &wi, Color &weight, float &pdf);
}  // namespace rdv::transparent
