#include "bsdfs/oren_nayar.h"
#include "bsdfs/cosine_lobe.h"
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

float pdf(const Lobe &, Vec3 wo, Vec3 wi) { return cosine_lobe_pdf(wo, wi); }

bool sample(const Lobe &lobe, Vec3 wo, Vec2 u, Vec3 &wi, Color &weight, float &pdf_out) {
  return sample_cosine_lobe(wo, u, wi, weight, pdf_out, [&](Vec3 w) { return eval(lobe, wo, w); });
}

}  // namespace rdv::oren_nayar
