#include "bsdfs/conductor.h"
#include "bsdfs/ggx_albedo.h"
#include "core/sampling.h"

namespace rdv::conductor {

namespace {

float ms_alpha(const Lobe &lobe) { return std::sqrt(lobe.ggx.ax * lobe.ggx.ay); }

// Probability of sampling the compensation lobe instead of the microfacet one.
float ms_probability(const Lobe &lobe, Vec3 wo) {
  if (!lobe.multiscatter) return 0;
  return clampf(1.0f - ggx_albedo(wo.z, ms_alpha(lobe), lobe.ggx.separable), 0.0f, 0.9f);
}

Color eval_single(const Lobe &lobe, Vec3 wo, Vec3 wi) {
  Vec3 h = normalize(wo + wi);
  float d = lobe.ggx.D(h);
  if (d == 0) return Color(0.0f);
  float g = lobe.ggx.G2(wo, wi);
  return lobe.fresnel(dot(wi, h)) * (d * g / (4.0f * wo.z * wi.z));
}

Color eval_multi(const Lobe &lobe, Vec3 wo, Vec3 wi) {
  float alpha = ms_alpha(lobe);
  const bool separable = lobe.ggx.separable;
  float eavg = ggx_average_albedo(alpha, separable);
  if (eavg >= 0.9999f) return Color(0.0f);
  Color favg = average_fresnel(lobe);
  Color fms = favg * favg * eavg / (Color(1.0f) - favg * (1.0f - eavg));
  float k = (1.0f - ggx_albedo(wo.z, alpha, separable)) * (1.0f - ggx_albedo(wi.z, alpha, separable)) /
            (kPi * (1.0f - eavg));
  return fms * k;
}

float pdf_single(const Lobe &lobe, Vec3 wo, Vec3 wi) {
  Vec3 h = normalize(wo + wi);
  float woh = dot(wo, h);
  if (woh <= 0) return 0;
  return lobe.ggx.D_visible(wo, h) / (4.0f * woh);
}

}  // namespace

Color average_fresnel(const Lobe &lobe) {
  switch (lobe.fresnel_mode) {
    case FresnelMode::Tint: return lobe.color;
    case FresnelMode::Schlick:
    case FresnelMode::Interpolated:  // FH's average as Schlick's factor's (1 / 21)
      return lobe.color * (lobe.f0 + (Color(1.0f) - lobe.f0) * (1.0f / 21.0f));
    case FresnelMode::Conductor: {  // Schlick's average around the normal-incidence value
      Color f0 = fresnel_conductor(1.0f, lobe.eta, lobe.k);
      return lobe.color * (f0 + (Color(1.0f) - f0) * (1.0f / 21.0f));
    }
    case FresnelMode::Dielectric: {
      float f0 = fresnel_dielectric(1.0f, lobe.ior);
      return lobe.color * (f0 + (1.0f - f0) / 21.0f);
    }
  }
  return lobe.color;
}

Color eval(const Lobe &lobe, Vec3 wo, Vec3 wi) {
  if (wo.z <= 0 || wi.z <= 0) return Color(0.0f);
  Color f = eval_single(lobe, wo, wi);
  if (lobe.multiscatter) f += eval_multi(lobe, wo, wi);
  return f;
}

float pdf(const Lobe &lobe, Vec3 wo, Vec3 wi) {
  if (wo.z <= 0 || wi.z <= 0) return 0;
  float p_ms = ms_probability(lobe, wo);
  return (1.0f - p_ms) * pdf_single(lobe, wo, wi) + p_ms * cosine_hemisphere_pdf(wi.z);
}

Color eval_and_pdf(const Lobe &lobe, Vec3 wo, Vec3 wi, float &pdf_out) {
  pdf_out = 0;
  if (wo.z <= 0 || wi.z <= 0) return Color(0.0f);
  // eval_single and pdf_single with their common terms computed once.
  Vec3 h = normalize(wo + wi);
  float d = lobe.ggx.D(h);
  float lambda_o = lobe.ggx.lambda(wo);
  float woh = dot(wo, h);
  Color f(0.0f);
  float p_single = 0;
  if (d != 0) {
    float g = lobe.ggx.G2_of_lambdas(lambda_o, lobe.ggx.lambda(wi));
    f = lobe.fresnel(dot(wi, h)) * (d * g / (4.0f * wo.z * wi.z));
  }
  if (woh > 0) p_single = 1.0f / (1.0f + lambda_o) * woh * d / wo.z / (4.0f * woh);
  if (!lobe.multiscatter) {
    pdf_out = p_single;
    return f;
  }
  float p_ms = ms_probability(lobe, wo);
  pdf_out = (1.0f - p_ms) * p_single + p_ms * cosine_hemisphere_pdf(wi.z);
  return f + eval_multi(lobe, wo, wi);
}

bool sample(const Lobe &lobe, Vec3 wo, Vec2 u, float uc, Vec3 &wi, Color &weight, float &pdf_out) {
  if (wo.z <= 0) return false;
  float p_ms = ms_probability(lobe, wo);
  if (p_ms > 0) {
    if (uc < p_ms) {
      wi = cosine_hemisphere(u);
    } else {
      Vec3 h = lobe.ggx.sample_visible_normal(wo, u);
      float woh = dot(wo, h);
      if (woh <= 0) return false;
      wi = h * (2.0f * woh) - wo;
    }
    if (wi.z <= 0) return false;
    pdf_out = pdf(lobe, wo, wi);
    if (!(pdf_out > 0)) return false;
    weight = eval(lobe, wo, wi) * (wi.z / pdf_out);
    return true;
  }
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
