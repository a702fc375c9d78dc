// Conventions (local frame, z = shading normal on wo's side): lobe.ior = eta is the
// IOR of the z < 0 side relative to the z > 0 side. Physically, radiance refracted into
// a denser medium grows by eta^2 (the basic radiance L / n^2 is what is conserved); like
// Cycles, whose images our users compare with, Radiance mode (camera paths) leaves that
// out, so a camera inside water or glass sees the world as bright as a camera in air
// does (a real camera's sensor sits behind a port, in air). Importance mode (light paths)
// then carries the 1 / eta^2, which keeps f_importance(wo, wi) = f_radiance(wi, wo)
// (Veach 1997, ch. 5.2): BDPT's strategies and Metropolis still agree with the path tracer.
#include "bsdfs/dielectric.h"

namespace rdv::dielectric {

namespace {

float refraction_scale(float eta, TransportMode mode) {
  return mode == TransportMode::Importance ? 1.0f / (eta * eta) : 1.0f;
}

// Generalised half vector of a refraction pair, facing +z; false if degenerate.
bool refraction_half_vector(Vec3 wo, Vec3 wi, float eta, Vec3 &h) {
  h = wo + wi * eta;
  float len2 = length_squared(h);
  if (!(len2 > 0)) return false;
  h = h / std::sqrt(len2);
  if (h.z < 0) h = -h;
  // Both directions must see the microfacet from the correct side.
  return dot(wo, h) > 0 && dot(wi, h) < 0;
}

// Cycles 3.4's rough glass (Lobe::macro_fresnel) weights reflection by F and refraction by
// max(1e-4, 1 - F), F the Fresnel of the camera-side direction at the shading normal (its
// sd->I). That is wo in Radiance mode, wi in Importance mode (a light path evaluates the
// adjoint), on its own side of the surface: so camera and light paths see one f.
float camera_side_fresnel(float eta, Vec3 wo, Vec3 wi, TransportMode mode) {
  if (mode == TransportMode::Radiance) return fresnel_dielectric(wo.z, eta);
  return wi.z > 0 ? fresnel_dielectric(wi.z, eta) : fresnel_dielectric(-wi.z, 1.0f / eta);
}
constexpr float kMinRefractionWeight = 1e-4f;  // Cycles 3.4's floor on 1 - F

// The chance a sample reflects: the facet's Fresnel, or with macro_fresnel wo's at the
// shading normal (kept below 1, so every direction the refraction weight reaches is sampled).
float reflect_probability(const Lobe &lobe, Vec3 wo, float woh) {
  if (lobe.reflection_only) return 1.0f;
  if (lobe.macro_fresnel) return std::min(fresnel_dielectric(wo.z, lobe.ior), 1.0f - kMinRefractionWeight);
  return fresnel_dielectric(woh, lobe.ior);
}

// The reflection's colour: the lobe's, or with FresnelMode::Interpolated (Cycles 3.4's
// Principled glass with Specular Tint) from f0 = the tint at normal incidence to white at
// grazing, by the facet's Fresnel (Lobe::fresnel at the half-vector).
Color reflection_color(const Lobe &lobe, float cos_h) {
  return lobe.fresnel_mode == FresnelMode::Interpolated ? lobe.fresnel(cos_h) : lobe.color;
}

}  // namespace

Color eval(const Lobe &lobe, Vec3 wo, Vec3 wi, TransportMode mode) {
  if (wo.z <= 0 || wi.z == 0) return Color(0.0f);
  const float eta = lobe.ior;
  if (wi.z > 0) {  // reflection
    if (lobe.refraction_only) return Color(0.0f);
    Vec3 h = normalize(wo + wi);
    float d = lobe.ggx.D(h);
    if (d == 0) return Color(0.0f);
    float F = lobe.macro_fresnel ? camera_side_fresnel(eta, wo, wi, mode) : fresnel_dielectric(dot(wo, h), eta);
    return reflection_color(lobe, dot(wo, h)) * (F * d * lobe.ggx.G2(wo, wi) / (4.0f * wo.z * wi.z));
  }
  Vec3 h;
  if (lobe.reflection_only || !refraction_half_vector(wo, wi, eta, h)) return Color(0.0f);
  float d = lobe.ggx.D(h);
  if (d == 0) return Color(0.0f);
  float woh = dot(wo, h), wih = dot(wi, h);
  float F = lobe.refraction_only ? 0.0f : fresnel_dielectric(woh, eta);
  if (F >= 1.0f) return Color(0.0f);  // total internal reflection
  if (lobe.macro_fresnel) F = std::min(camera_side_fresnel(eta, wo, wi, mode), 1.0f - kMinRefractionWeight);
  float denom = sqr(wih * eta + woh);
  float f = (1.0f - F) * d * lobe.ggx.G2(wo, wi) * eta * eta * std::fabs(wih * woh) / (denom * wo.z * std::fabs(wi.z));
  return lobe.color * (f * refraction_scale(eta, mode));
}

float pdf(const Lobe &lobe, Vec3 wo, Vec3 wi) {
  if (wo.z <= 0 || wi.z == 0) return 0;
  const float eta = lobe.ior;
  if (wi.z > 0) {
    if (lobe.refraction_only) return 0;
    Vec3 h = normalize(wo + wi);
    float woh = dot(wo, h);
    if (woh <= 0) return 0;
    return reflect_probability(lobe, wo, woh) * lobe.ggx.D_visible(wo, h) / (4.0f * woh);
  }
  Vec3 h;
  if (lobe.reflection_only || !refraction_half_vector(wo, wi, eta, h)) return 0;
  float woh = dot(wo, h), wih = dot(wi, h);
  float F = lobe.refraction_only ? (fresnel_dielectric(woh, eta) >= 1.0f ? 1.0f : 0.0f) : reflect_probability(lobe, wo, woh);
  float jacobian = eta * eta * std::fabs(wih) / sqr(wih * eta + woh);
  return (1.0f - F) * lobe.ggx.D_visible(wo, h) * jacobian;
}

bool sample(const Lobe &lobe, Vec3 wo, Vec2 u, float uc, Vec3 &wi, Color &weight, float &pdf_out, TransportMode mode) {
  if (wo.z <= 0) return false;
  const float eta = lobe.ior;
  Vec3 h = lobe.ggx.sample_visible_normal(wo, u);
  float woh = dot(wo, h);
  if (woh <= 0) return false;
  float F = reflect_probability(lobe, wo, woh);  // uc chooses reflection with probability F
  if (lobe.refraction_only) {
    if (F >= 1.0f) return false;  // total internal reflection: the Refraction BSDF is black
    F = 0.0f;
  }
  float dvis = lobe.ggx.D_visible(wo, h);
  if (uc < F) {
    wi = h * (2.0f * woh) - wo;
    if (wi.z <= 0) return false;
    pdf_out = F * dvis / (4.0f * woh);
    weight = lobe.macro_fresnel ? eval(lobe, wo, wi, mode) * (wi.z / pdf_out)
                                : reflection_color(lobe, woh) * (lobe.ggx.G2(wo, wi) / lobe.ggx.G1(wo));
  } else {
    // Fails only where the facet reflects totally: never when F is the facet's and below 1;
    // with macro_fresnel, such a sample is lost (f there is reflection, sampled above).
    if (!refract(wo, h, eta, wi)) return false;
    if (wi.z >= 0) return false;
    float wih = dot(wi, h);
    pdf_out = (1.0f - F) * dvis * eta * eta * std::fabs(wih) / sqr(wih * eta + woh);
    weight = lobe.macro_fresnel ? eval(lobe, wo, wi, mode) * (-wi.z / pdf_out)
                                : lobe.color * (lobe.ggx.G2(wo, wi) / lobe.ggx.G1(wo) * refraction_scale(eta, mode));
  }
  return pdf_out > 0 && std::isfinite(pdf_out);
}

bool sample_smooth(const Lobe &lobe, Vec3 wo, Vec2 u, Vec3 &wi, Color &weight, float &pdf_out, TransportMode mode) {
  if (wo.z <= 0) return false;
  const float eta = lobe.ior;
  // What reflection and refraction carry (for a smooth surface the shading normal's Fresnel
  // is the facet's, so macro_fresnel changes nothing), and the chance of each.
  const float F = fresnel_dielectric(wo.z, eta);
  float reflected = F, refracted = 1.0f - F;
  if (F == 0 && lobe.reflection_only) return false;  // nothing reflects (an IOR of 1)
  if (lobe.refraction_only) {
    if (F >= 1.0f) return false;
    reflected = 0;
    if (!lobe.macro_fresnel) refracted = 1;  // the Refraction BSDF: no Fresnel
  }
  if (lobe.reflection_only) refracted = 0;
  const float p_reflect = lobe.reflection_only ? 1.0f : lobe.refraction_only ? 0.0f : F;
  if (u.x < p_reflect) {
    wi = Vec3(-wo.x, -wo.y, wo.z);
    pdf_out = p_reflect;
    weight = reflection_color(lobe, wo.z) * (reflected / p_reflect);
    return true;
  }
  if (!refract(wo, Vec3(0, 0, 1), eta, wi)) return false;
  pdf_out = 1.0f - p_reflect;
  weight = lobe.color * (refracted / pdf_out * refraction_scale(eta, mode));
  return true;
}

}  // namespace rdv::dielectric
