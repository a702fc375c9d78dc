#include "bsdfs/sheen.h"
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

float pdf(const Lobe &, Vec3 wo, Vec3 wi) {
  if (wo.z <= 0) return 0;
  return cosine_hemisphere_pdf(wi.z);
}

bool sample(const Lobe &lobe, Vec3 wo, Vec2 u, Vec3 &wi, Color &weight, float &pdf_out) {
  if (wo.z <= 0) return false;
  wi = cosine_hemisphere(u);
  pdf_out = cosine_hemisphere_pdf(wi.z);
  if (pdf_out <= 0) return false;
  weight = eval(lobe, wo, wi) * (wi.z / pdf_out);
  return true;
}

}  // namespace rdv::sheen
