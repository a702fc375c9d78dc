// Conductor reflection: GGX microfacet with visible-normal sampling, and the perfect
// mirror it becomes below Cycles' smoothness limit.
#pragma once
#include "bsdfs/bsdf.h"

namespace rdv::conductor {
Color eval(const Lobe &lobe, Vec3 wo, Vec3 wi);
float pdf(const Lobe &lobe, Vec3 wo, Vec3 wi);
bool sample(const Lobe &lobe, Vec3 wo, Vec2 u, Vec3 &wi, Color &weight, float &pdf);
bool sample_specular(const Lobe &lobe, Vec3 wo, Vec3 &wi, Color &weight);
}  // namespace rdv::conductor
