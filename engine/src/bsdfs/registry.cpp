#include "bsdfs/registry.h"

namespace rdv {

static Lobe lambert(Color c) {
  Lobe l;
  l.type = LobeType::Lambert;
  l.color = c;
  return l;
}

static Lobe ggx(float roughness_x, float roughness_y, bool gold_fresnel = false) {
  Lobe l;
  l.ggx = {roughness_x * roughness_x, roughness_y * roughness_y};
  l.type = l.ggx.is_smooth() ? LobeType::SpecularConductor : LobeType::GgxConductor;
  l.color = Color(1.0f);
  if (gold_fresnel) {
    l.fresnel_mode = FresnelMode::Conductor;
    l.eta = {0.143f, 0.374f, 1.442f};
    l.k = {3.983f, 2.385f, 1.603f};
  }
  return l;
}

static Lobe multi_ggx(float roughness_x, float roughness_y, Color tint = Color(1.0f)) {
  Lobe l = ggx(roughness_x, roughness_y);
  l.multiscatter = true;
  l.color = tint;
  return l;
}

// Principled specular / clearcoat: Schlick Fresnel from f0.
static Lobe schlick_ggx(float roughness, Color f0, float scale = 1.0f) {
  Lobe l = ggx(roughness, roughness);
  l.fresnel_mode = FresnelMode::Schlick;
  l.f0 = f0;
  l.color = Color(scale);
  return l;
}

// Cycles 3.4's Principled clearcoat (GTR1; alpha = roughness^2), IOR 1.5's Fresnel.
static Lobe gtr1_clearcoat(float roughness) {
  Lobe l = ggx(roughness, roughness);
  l.type = LobeType::Clearcoat;
  l.fresnel_mode = FresnelMode::Dielectric;
  l.ior = 1.5f;
  return l;
}

// Glass: ior is relative (inside / outside); < 1 is the view from inside.
static Lobe dielectric_lobe(float roughness, float ior) {
  Lobe l;
  l.ggx = {roughness * roughness, roughness * roughness};
  l.type = l.ggx.is_smooth() ? LobeType::SmoothDielectric : LobeType::GgxDielectric;
  l.ior = ior;
  l.color = Color(1.0f);
  return l;
}

static Lobe refraction(float roughness, float ior) {
  Lobe l = dielectric_lobe(roughness, ior);
  l.refraction_only = true;
  return l;
}

// Cycles 3.4's separable shadowing (Blender 3.x materials, microfacet.h).
static Lobe separable(Lobe l) {
  l.ggx.separable = true;
  return l;
}

// Cycles 3.4's rough glass: separable shadowing and the split at the shading normal's Fresnel.
static Lobe cycles34(Lobe l) {
  l.ggx.separable = true;
  l.macro_fresnel = true;
  return l;
}

static Lobe part(Lobe l, bool reflection) {
  (reflection ? l.reflection_only : l.refraction_only) = true;
  return l;
}

// Cycles 3.4's Principled glass reflection with Specular Tint: tinted f0 toward white by FH.
static Lobe tinted(Lobe l, Color f0) {
  l.fresnel_mode = FresnelMode::Interpolated;
  l.f0 = f0;
  return l;
}

static Lobe simple(LobeType type, Color c, float sigma = 0) {
  Lobe l;
  l.type = type;
  l.color = c;
  l.sigma = sigma;
  return l;
}

const std::vector<LobeTestCase> &lobe_test_cases() {
  static const std::vector<LobeTestCase> cases = {
      {"lambert_white", lambert(Color(1.0f)), true},
      {"lambert_grey", lambert(Color(0.5f)), false},
      {"ggx_r1e-4_mirror", ggx(1e-4f, 1e-4f), false},
      {"ggx_r0.05", ggx(0.05f, 0.05f), false},
      {"ggx_r0.1", ggx(0.1f, 0.1f), false},
      {"ggx_r0.3", ggx(0.3f, 0.3f), false},
      {"ggx_r0.6", ggx(0.6f, 0.6f), false},
      {"ggx_r1", ggx(1.0f, 1.0f), false},
      {"ggx_aniso_0.1x0.5", ggx(0.1f, 0.5f), false},
      {"ggx_gold_r0.3", ggx(0.3f, 0.3f, true), false},
      // Multiscatter GGX (Kulla-Conty): white version keeps all energy (furnace within 1%).
      {"multi_ggx_r0.3", multi_ggx(0.3f, 0.3f), true},
      {"multi_ggx_r0.6", multi_ggx(0.6f, 0.6f), true},
      {"multi_ggx_r1", multi_ggx(1.0f, 1.0f), true},
      {"multi_ggx_aniso_0.2x0.8", multi_ggx(0.2f, 0.8f), false},
      {"multi_ggx_tinted_r0.7", multi_ggx(0.7f, 0.7f, Color(0.9f, 0.6f, 0.3f)), false},
      // Separable shadowing: Multiscatter's compensation from its own albedo table (furnace 1).
      {"ggx_r0.6_separable", separable(ggx(0.6f, 0.6f)), false},
      {"ggx_aniso_0.1x0.5_separable", separable(ggx(0.1f, 0.5f)), false},
      {"multi_ggx_r0.6_separable", separable(multi_ggx(0.6f, 0.6f)), true},
      {"multi_ggx_r1_separable", separable(multi_ggx(1.0f, 1.0f)), true},
      {"principled_specular_r0.4", schlick_ggx(0.4f, Color(0.04f)), false},
      {"clearcoat_r0.1", schlick_ggx(0.1f, Color(0.04f), 0.25f), false},
      {"clearcoat_gtr1_r0.05", gtr1_clearcoat(0.05f), false},
      {"clearcoat_gtr1_r0.3", gtr1_clearcoat(0.3f), false},
      {"clearcoat_gtr1_r1", gtr1_clearcoat(1.0f), false},
      // Dielectrics: smooth (delta) and rough, entering (ior > 1) and leaving (ior < 1).
      {"glass_smooth_1.5", dielectric_lobe(0.0f, 1.5f), true},
      {"glass_smooth_inside_1.5", dielectric_lobe(0.0f, 1.0f / 1.5f), false},
      {"glass_smooth_1.0001", dielectric_lobe(0.0f, 1.0001f), true},
      {"glass_smooth_4", dielectric_lobe(0.0f, 4.0f), true},
      {"glass_r1e-4_1.5", dielectric_lobe(1e-4f, 1.5f), true},
      // Rough glass below roughness 0.2 (or with IOR near 1) refracts into a spike at
      // the pole at normal incidence that the chi-square grid's cell integration cannot
      // resolve; those limits are covered by the smooth cases (the model switches at
      // Cycles' smoothness limit) and by test_material_dielectric.cpp.
      {"glass_r0.2_1.5", dielectric_lobe(0.2f, 1.5f), false},
      {"glass_r0.3_1.5", dielectric_lobe(0.3f, 1.5f), false},
      {"glass_r0.3_inside_1.5", dielectric_lobe(0.3f, 1.0f / 1.5f), false},
      {"glass_r1_1.5", dielectric_lobe(1.0f, 1.5f), false},
      {"glass_r0.5_4", dielectric_lobe(0.5f, 4.0f), false},
      {"glass_r0.5_inside_4", dielectric_lobe(0.5f, 0.25f), false},
      {"glass_r0.5_1.1", dielectric_lobe(0.5f, 1.1f), false},
      {"glass_r0.5_1.5_cycles34", cycles34(dielectric_lobe(0.5f, 1.5f)), false},
      {"glass_r0.5_inside_1.5_cycles34", cycles34(dielectric_lobe(0.5f, 1.0f / 1.5f)), false},
      {"glass_r0.2_1.5_cycles34", cycles34(dielectric_lobe(0.2f, 1.5f)), false},
      // Cycles 3.4's Principled glass: its reflection and its refraction as lobes of their own.
      {"glass_reflection_r0.3_1.5_cycles34", part(cycles34(dielectric_lobe(0.3f, 1.5f)), true), false},
      {"glass_refraction_r0.6_1.5_cycles34", part(cycles34(dielectric_lobe(0.6f, 1.5f)), false), false},
      {"glass_refraction_r1_inside_1.3_cycles34", part(cycles34(dielectric_lobe(1.0f, 1.0f / 1.3f)), false), false},
      {"glass_smooth_reflection_1.5_cycles34", part(cycles34(dielectric_lobe(0.0f, 1.5f)), true), false},
      {"glass_tinted_reflection_r0.3_1.5_cycles34",
       tinted(part(cycles34(dielectric_lobe(0.3f, 1.5f)), true), Color(0.9f, 0.6f, 0.3f)), false},
      {"glass_tinted_smooth_reflection_1.5_cycles34",
       tinted(part(cycles34(dielectric_lobe(0.0f, 1.5f)), true), Color(0.9f, 0.6f, 0.3f)), false},
      {"glass_smooth_refraction_1.5_cycles34", part(cycles34(dielectric_lobe(0.0f, 1.5f)), false), false},
      // Refraction BSDF (transmission only, no Fresnel): lossless except total internal reflection.
      {"refraction_smooth_1.5", refraction(0.0f, 1.5f), true},
      {"refraction_r0.4_1.5", refraction(0.4f, 1.5f), false},
      {"refraction_r1_inside_1.3", refraction(1.0f, 1.0f / 1.3f), false},
      {"oren_nayar_0.5", simple(LobeType::OrenNayar, Color(1.0f), 0.5f), false},
      {"oren_nayar_1", simple(LobeType::OrenNayar, Color(1.0f), 1.0f), false},
      {"oren_nayar_0", simple(LobeType::OrenNayar, Color(1.0f), 0.0f), true},
      {"translucent", simple(LobeType::Translucent, Color(1.0f)), true},
      {"transparent", simple(LobeType::Transparent, Color(1.0f)), true},
      {"sheen", simple(LobeType::Sheen, Color(1.0f)), false},
      // Principled diffuse (Disney, Cycles 3.4): retro-reflection exceeds albedo 1 at
      // grazing angles for high roughness (chi-square / weight / reciprocity still apply).
      {"principled_diffuse_r0", simple(LobeType::PrincipledDiffuse, Color(0.8f), 0.0f), false, true},
      {"principled_diffuse_r0.5", simple(LobeType::PrincipledDiffuse, Color(0.8f), 0.5f), false, true},
      {"principled_diffuse_r1", simple(LobeType::PrincipledDiffuse, Color(0.8f), 1.0f), false, true},
  };
  return cases;
}

}  // namespace rdv
