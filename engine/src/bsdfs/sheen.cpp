#include "bsdfs/sheen.h"
#include "bsdfs/cosine_lobe.h"
#include "core/sampling.h"

namespace rdv::sheen {

Color eval(const Lobe &lobe, Vec3 wo, Vec3 wi) {
  if (wo.z <= 0 || wi.z <= 0) return Color(0.0f);
  Vec3 h = wo + wi;
  float len = length(h);
  if (!(len > 0)) return Color(0.0f);
  float m = clampf(1.0f - std::fabs(dot(wi, h)) / len, 0.0f, 1.0f), m2 = m * m;
  return lobe.color * (m2 * m2 * m);
}

float pdf(const Lobe &, Vec3 wo, Vec3 wi) { return cosine_lobe_pdf(wo, wi); }

bool sample(const Lobe &lobe, Vec3 wo, Vec2 u, Vec3 &wi, Color &weight, float &pdf_out) {
  return sample_cosine_lobe(wo, u, wi, weight, pdf_out, [&](Vec3 w) { return eval(lobe, wo, w); });
}

}  // namespace rdv::sheen
