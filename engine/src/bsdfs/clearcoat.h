// The clearcoat of Blender 3.4's Principled BSDF (Cycles' microfacet_ggx_clearcoat):
// Burley's GTR1 distribution of alpha = clearcoat roughness^2, whose long tails make the coat's
// highlight a sharp core in a wide glow, shadowed by Smith's separable G1(wo) G1(wi) of a GGX
// surface at the fixed alpha 0.25 (Disney's choice), and the lobe's Fresnel (Cycles: IOR 1.5):
//   f = F D_GTR1(h) G1(wo) G1(wi) / (4 cos_o cos_i).
// Sampled by h from D_GTR1(h) cos(theta_h) (exactly its density; Cycles 3.4 draws GGX normals
// and reports the GTR1 density, so its BSDF-sampled estimate differs from ours, not its f).
#pragma once
#include "bsdfs/bsdf.h"

namespace rdv::clearcoat {
// The GTR1 alpha is lobe.ggx.ax.
Color eval(const Lobe &lobe, Vec3 wo, Vec3 wi);
float pdf(const Lobe &lobe, Vec3 wo, Vec3 wi);
bool sample(const Lobe &lobe, Vec3 wo, Vec2 u, Vec3 &wi, Color &weight, float &pdf);
}  // namespace rdv::clearcoat
