#include "bsdfs/principled_diffuse.h"
#include "bsdfs/cosine_lobe.h"
#include "core/sampling.h"

namespace rdv::principled_diffuse {

static float schlick_weight(float c) {
  float m = clampf(1.0f - c, 0.0f, 1.0f), m2 = m * m;
  return m2 * m2 * m;
}

Color eval(const Lobe &lobe, Vec3 wo, Vec3 wi) {
  if (wo.z <= 0 || wi.z <= 0) return Color(0.0f);
  float fv = schlick_weight(wo.z), fl = schlick_weight(wi.z);
  float f = (1.0f - 0.5f * fv) * (1.0f - 0.5f * fl);
  float rr = clampf(lobe.sigma, 0.0f, 1.0f) * (dot(wi, wo) + 1.0f);
  f += rr * (fl + fv + fl * fv * (rr - 1.0f));
  return lobe.color * (std::max(f, 0.0f) * kInvPi);
}

float pdf(const Lobe &, Vec3 wo, Vec3 wi) { return cosine_lobe_pdf(wo, wi); }

bool sample(const Lobe &lobe, Vec3 wo, Vec2 u, Vec3 &wi, Color &weight, float &pdf_out) {
  return sample_cosine_lobe(wo, u, wi, weight, pdf_out, [&](Vec3 w) { return eval(lobe, wo, w); });
}

}  // namespace rdv::principled_diffuse
