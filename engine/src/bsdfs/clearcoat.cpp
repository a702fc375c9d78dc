#include "bsdfs/clearcoat.h"
#include <cmath>

namespace rdv::clearcoat {

namespace {

// D_GTR1(h) = (a^2 - 1) / (pi ln(a^2) (1 + (a^2 - 1) cos^2)); the denominator's last factor as
// a^2 cos^2 + sin^2, which keeps its precision near the pole when a^2 is tiny (1e-6).
float gtr1(float alpha, Vec3 h) {
  const float a2 = alpha * alpha;
  if (a2 >= 1.0f - 1e-4f) return kInvPi;  // the limit alpha -> 1
  const float t = a2 * h.z * h.z + (h.x * h.x + h.y * h.y);
  return (a2 - 1.0f) / (kPi * std::log(a2) * t);
}

// Smith's G1 of a GGX surface of alpha 0.25 (Cycles 3.4: the clearcoat's fixed shadowing alpha).
float g1_quarter(float cos_theta) {
  const float c2 = cos_theta * cos_theta;
  return 2.0f / (1.0f + std::sqrt(1.0f + 0.0625f * (1.0f - c2) / c2));
}

}  // namespace

Color eval(const Lobe &lobe, Vec3 wo, Vec3 wi) {
  if (wo.z <= 0 || wi.z <= 0) return Color(0.0f);
  const Vec3 h = normalize(wo + wi);
  const float d = gtr1(lobe.ggx.ax, h);
  return lobe.fresnel(dot(wi, h)) * (d * g1_quarter(wo.z) * g1_quarter(wi.z) / (4.0f * wo.z * wi.z));
}

float pdf(const Lobe &lobe, Vec3 wo, Vec3 wi) {
  if (wo.z <= 0 || wi.z <= 0) return 0;
  const Vec3 h = normalize(wo + wi);
  return gtr1(lobe.ggx.ax, h) * h.z / (4.0f * dot(wo, h));
}

bool sample(const Lobe &lobe, Vec3 wo, Vec2 u, Vec3 &wi, Color &weight, float &pdf_out) {
  if (wo.z <= 0) return false;
  // cos^2(theta_h) by inverting the CDF of D_GTR1 cos over the hemisphere (Burley 2012).
  // sin^2 from its own expression: 1 - cos^2 would lose the narrow lobe's angles to rounding.
  const float a2 = lobe.ggx.ax * lobe.ggx.ax;
  float cos2 = 1.0f - u.x, sin2 = u.x;
  if (a2 < 1.0f - 1e-4f) {
    const float p = std::pow(a2, 1.0f - u.x);
    cos2 = (1.0f - p) / (1.0f - a2);
    sin2 = (p - a2) / (1.0f - a2);
  }
  const float cos_h = std::sqrt(clampf(cos2, 0.0f, 1.0f)), sin_h = std::sqrt(clampf(sin2, 0.0f, 1.0f));
  const float phi = 2.0f * kPi * u.y;
  const Vec3 h(sin_h * std::cos(phi), sin_h * std::sin(phi), cos_h);
  const float woh = dot(wo, h);
  if (woh <= 0) return false;
  wi = h * (2.0f * woh) - wo;
  if (wi.z <= 0) return false;
  pdf_out = pdf(lobe, wo, wi);
  if (!(pdf_out > 0)) return false;
  weight = eval(lobe, wo, wi) * (wi.z / pdf_out);
  return true;
}

}  // namespace rdv::clearcoat
