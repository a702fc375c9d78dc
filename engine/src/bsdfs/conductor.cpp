#include "bsdfs/conductor.h"

namespace rdv::conductor {

Color eval(const Lobe &lobe, Vec3 wo, Vec3 wi) {
  if (wo.z <= 0 || wi.z <= 0) return Color(0.0f);
  Vec3 h = normalize(wo + wi);
  float d = lobe.ggx.D(h);
  if (d == 0) return Color(0.0f);
  float g = lobe.ggx.G2(wo, wi);
  return lobe.fresnel(dot(wi, h)) * (d * g / (4.0f * wo.z * wi.z));
}

float pdf(const Lobe &lobe, Vec3 wo, Vec3 wi) {
  if (wo.z <= 0 || wi.z <= 0) return 0;
  Vec3 h = normalize(wo + wi);
  float woh = dot(wo, h);
  if (woh <= 0) return 0;
  return lobe.ggx.D_visible(wo, h) / (4.0f * woh);
}

bool sample(const Lobe &lobe, Vec3 wo, Vec2 u, Vec3 &wi, Color &weight, float &pdf_out) {
  if (wo.z <= 0) return false;
  Vec3 h = lobe.ggx.sample_visible_normal(wo, u);
  float woh = dot(wo, h);
  if (woh <= 0) return false;
  wi = h * (2.0f * woh) - wo;
  if (wi.z <= 0) return false;  // reflected below the macro surface: absorbed (single scattering)
  pdf_out = lobe.ggx.D_visible(wo, h) / (4.0f * woh);
  if (!(pdf_out > 0)) return false;
  // f * cos / pdf = F * G2 / G1(wo) for VNDF sampling.
  weight = lobe.fresnel(woh) * (lobe.ggx.G2(wo, wi) / lobe.ggx.G1(wo));
  return true;
}

bool sample_specular(const Lobe &lobe, Vec3 wo, Vec3 &wi, Color &weight) {
  if (wo.z <= 0) return false;
  wi = Vec3(-wo.x, -wo.y, wo.z);
  weight = lobe.fresnel(wo.z);
  return true;
}

}  // namespace rdv::conductor
