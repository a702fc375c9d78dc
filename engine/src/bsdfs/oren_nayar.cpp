#include "bsdfs/oren_nayar.h"
#include "core/sampling.h"

namespace rdv::oren_nayar {

Color eval(const Lobe &lobe, Vec3 wo, Vec3 wi) {
  if (wo.z <= 0 || wi.z <= 0) return Color(0.0f);
  float sigma = clampf(lobe.sigma, 0.0f, 1.0f);
  float a = 1.0f / (kPi + ((3.0f * kPi - 4.0f) / 6.0f) * sigma), b = sigma * a;
  float t = dot(wo, wi) - wo.z * wi.z;  // cos(phi) sin_o sin_i
  if (t > 0) t /= std::max(wo.z, wi.z);
  return lobe.color * std::max(0.0f, a + b * t);
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

}  // namespace rdv::oren_nayar
