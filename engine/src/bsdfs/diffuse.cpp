#include "bsdfs/diffuse.h"
#include "bsdfs/cosine_lobe.h"
#include "core/sampling.h"

namespace rdv::diffuse {

Color eval(const Lobe &lobe, Vec3 wo, Vec3 wi) {
  if (wo.z <= 0 || wi.z <= 0) return Color(0.0f);
  return lobe.color * kInvPi;
}

float pdf(const Lobe &, Vec3 wo, Vec3 wi) { return cosine_lobe_pdf(wo, wi); }

bool sample(const Lobe &lobe, Vec3 wo, Vec2 u, Vec3 &wi, Color &weight, float &pdf_out) {
  return sample_cosine_lobe(wo, u, wi, weight, pdf_out, [&](Vec3) { return lobe.color * kInvPi; });
}

}  // namespace rdv::diffuse
