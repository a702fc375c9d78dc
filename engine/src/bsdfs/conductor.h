// Conductor reflection: GGX microfacet with visible-normal sampling, and the perfect
// mirror it becomes below Cycles' smoothness limit. With lobe.multiscatter, the
// Kulla-Conty energy-compensation term (ggx_albedo.h) is added so rough metals do
// not darken (Cycles' Multiscatter GGX); it is sampled with a cosine lobe chosen
// with probability 1 - E(wo).
#pragma once
#include "bsdfs/bsdf.h"

namespace rdv::conductor {
Color eval(const Lobe &lobe, Vec3 wo, Vec3 wi);
float pdf(const Lobe &lobe, Vec3 wo, Vec3 wi);
// eval and pdf together: the half vector, D and Lambda(wo) are shared.
Color eval_and_pdf(const Lobe &lobe, Vec3 wo, Vec3 wi, float &pdf);
bool sample(const Lobe &lobe, Vec3 wo, Vec2 u, float uc, Vec3 &wi, Color &weight, float &pdf);
bool sample_specular(const Lobe &lobe, Vec3 wo, Vec3 &wi, Color &weight);
// Cosine-weighted hemispherical average of the lobe's Fresnel term.
Color average_fresnel(const Lobe &lobe);
}  // namespace rdv::conductor
