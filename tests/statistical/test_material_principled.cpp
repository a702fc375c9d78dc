// Whole materials (Principled BSDF, mixes, textured weights) as the path tracer sees
// them: the Bsdf's lobe mixture samples its own pdf (chi-square, on the full sphere,
// transmission included), sample weights equal eval / pdf in both transport modes,
// and energy: mixes and lossless combinations never reflect more than they receive.
// False-alarm rate: 1% for the suite's chi-square tests (Sidak-corrected); the other
// checks are deterministic with fixed seeds and 4-sigma margins.
#include <gtest/gtest.h>
#include "bsdfs/material.h"
#include "test_materials.h"
#include "fresnel_reference.h"
#include "chi_square.h"
#include "core/hash.h"

namespace test_material_principled {

using namespace rdv;

namespace {

// lossless: keeps all energy (white furnace within 1.5%; 4% at 87 degrees). additive: the Principled
// BSDF's "layering": "additive" (Cycles 3.4 exactly: Disney diffuse, layers added
// without albedo scaling) can exceed 1 at grazing incidence; checked at wo.z >= 0.5 only.
// The default energy-conserving Principled BSDF is checked everywhere.
struct Case { const char *name; const char *json; bool lossless; bool additive = false; };

const std::vector<Case> &cases() {
  static const std::vector<Case> c = {
      {"principled_default", R"({"type":"principled"})", false},
      {"principled_metal_aniso", R"({"type":"principled","base_color":[0.9,0.6,0.3],"metallic":1,"roughness":0.4,"anisotropic":0.7,"anisotropic_rotation":0.1})", false},
      {"principled_multiscatter_metal", R"({"type":"principled","base_color":[1,1,1],"metallic":1,"roughness":0.8,"distribution":"MULTI_GGX"})", false},
      {"principled_rough_glass", R"({"type":"principled","transmission":1,"roughness":0.3,"ior":1.5,"base_color":[1,1,1]})", false},
      {"principled_sheen_clearcoat", R"({"type":"principled","sheen":1,"sheen_tint":0.5,"clearcoat":1,"clearcoat_roughness":0.2,"roughness":0.6})", false},
      {"principled_4x_names", R"({"type":"principled","coat_weight":0.5,"coat_roughness":0.2,"sheen_weight":0.5,"specular_ior_level":0.5,"transmission_weight":0.2,"roughness":0.5})", false},
      {"principled_white_furnace", R"({"type":"principled","base_color":[1,1,1],"sheen":1,"clearcoat":1,"clearcoat_roughness":0.2,"roughness":0.6})", true},
      {"principled_white_smooth_furnace", R"({"type":"principled","base_color":[1,1,1],"roughness":0.1,"clearcoat":0.5,"clearcoat_roughness":0.3})", true},
      {"principled_additive", R"({"type":"principled","layering":"additive","sheen":1,"clearcoat":1,"clearcoat_roughness":0.2})", false, true},
      {"oren_nayar", R"({"type":"diffuse","color":[0.9,0.9,0.9],"roughness":0.8})", false},
      {"rough_refraction", R"({"type":"refraction","roughness":0.3,"ior":1.33})", false},
      {"mix_diffuse_rough_glass", R"({"type":"mix","fac":0.3,"shader1":{"type":"diffuse","color":[1,1,1]},"shader2":{"type":"glass","roughness":0.4,"ior":1.45}})", false},
      {"mix_translucent_glossy", R"({"type":"mix","fac":0.5,"shader1":{"type":"translucent","color":[1,1,1]},"shader2":{"type":"glossy","color":[1,1,1],"roughness":0.3,"distribution":"MULTI_GGX"}})", true},
      {"add_halves", R"({"type":"add","shader1":{"type":"diffuse","color":[0.5,0.5,0.5]},"shader2":{"type":"glossy","color":[0.5,0.5,0.5],"roughness":0.5}})", false},
      {"mix_textured_fac", R"({"type":"mix","fac":{"node":"checker","scale":3},"shader1":{"type":"diffuse"},"shader2":{"type":"glossy","roughness":0.2}})", false},
      // Mix Shader factors by the viewing direction (Fresnel, Layer Weight: view_factor.h).
      {"mix_fresnel", R"({"type":"mix","fac":{"node":"fresnel","ior":1.45},"shader1":{"type":"diffuse","color":[0.8,0.3,0.2]},"shader2":{"type":"glossy","roughness":0.2}})", false},
      {"mix_facing_rough_glass", R"({"type":"mix","fac":{"node":"layer_weight","output":"facing","blend":0.3},"shader1":{"type":"diffuse"},"shader2":{"type":"glass","roughness":0.3,"ior":1.5}})", false},
      {"mix_layer_fresnel_lossless", R"({"type":"mix","fac":{"node":"layer_weight","blend":0.4},"shader1":{"type":"translucent","color":[1,1,1]},"shader2":{"type":"glossy","color":[1,1,1],"roughness":0.3,"distribution":"MULTI_GGX"}})", true},
      {"leaf_two_sided_with_alpha", R"({"type":"mix","fac":0.4,"shader1":{"type":"transparent"},"shader2":{"type":"mix","fac":{"node":"backfacing"},"shader1":{"type":"diffuse","color":[0.2,0.7,0.2]},"shader2":{"type":"glossy","roughness":0.3}}})", false},
      {"nested_view_factors", R"({"type":"mix","fac":{"node":"layer_weight","output":"facing","blend":0.7},"shader1":{"type":"mix","fac":{"node":"fresnel","ior":1.3},"shader1":{"type":"diffuse"},"shader2":{"type":"principled","roughness":0.4}},"shader2":{"type":"glossy","roughness":0.05}})", false},
  };
  return c;
}

const std::vector<Vec3> &incident() {
  static const std::vector<Vec3> d = {normalize(Vec3(0, 0, 1)), normalize(Vec3(0.5f, 0.2f, 0.7f)),
                                      normalize(Vec3(0.8f, 0.3f, 0.05f))};
  return d;
}

Material material(const char *json) { return test::material_from_json(json); }
ShadingPoint point() { return test::flat_point(); }

}  // namespace

TEST(MaterialSampling, ChiSquareOfWholeMaterials) {
  const double alpha = test::sidak(0.01, int(cases().size() * incident().size()));
  uint64_t seed = 100;
  for (const Case &c : cases()) {
    Material m = material(c.json);
    for (Vec3 wo : incident()) {
      SCOPED_TRACE(std::string(c.name) + " wo.z=" + std::to_string(wo.z));
      Bsdf bsdf = m.make_bsdf(point(), wo);
      Pcg32 lobe_rng(seed * 7 + 1);
      auto r = test::chi_square_directions(
          [&](Vec2 u, Vec3 &wi) {
            BsdfSample s;
            if (!bsdf.sample(wo, lobe_rng.next_float(), u, TransportMode::Radiance, s) || s.is_delta) return false;
            wi = s.wi;
            return true;
          },
          [&](Vec3 wi) { return bsdf.pdf(wo, wi); }, 100000, seed++);
      EXPECT_FALSE(r.impossible_sample) << r.detail;
      EXPECT_GT(r.p_value, alpha) << r.detail;
    }
  }
}

TEST(MaterialSampling, WeightIsEvalOverPdfInBothModes) {
  Pcg32 rng(3);
  for (const Case &c : cases()) {
    Material m = material(c.json);
    for (Vec3 wo : incident()) {
      Bsdf bsdf = m.make_bsdf(point(), wo);
      for (int i = 0; i < 500; ++i) {
        TransportMode mode = (i & 1) ? TransportMode::Importance : TransportMode::Radiance;
        BsdfSample s;
        float ul = rng.next_float(), a = rng.next_float();
        if (!bsdf.sample(wo, ul, {a, rng.next_float()}, mode, s) || s.is_delta) continue;
        Color f = bsdf.eval(wo, s.wi, mode);
        float pdf = bsdf.pdf(wo, s.wi);
        Color expected = f / pdf;
        for (int k = 0; k < 3; ++k)
          EXPECT_NEAR(s.weight[k], expected[k], 2e-3f * std::max(1.0f, expected[k])) << c.name;
        // The combined evaluation (next-event estimation) gives what eval and pdf give alone.
        float pdf_both;
        Color f_both = bsdf.eval_and_pdf(wo, s.wi, mode, pdf_both);
        EXPECT_NEAR(pdf_both, pdf, 1e-5f * pdf) << c.name;
        for (int k = 0; k < 3; ++k) EXPECT_NEAR(f_both[k], f[k], 1e-5f * std::max(1.0f, f[k])) << c.name;
      }
    }
  }
}

// Directional albedo by Monte Carlo (Radiance mode: scattered flux; Importance mode
// carries refraction's 1 / eta^2). Mixes of
// energy-conserving closures stay <= 1 (4 standard errors); a lossless mix (translucent
// + multiscatter white glossy) keeps 1 within 1.5%.
TEST(MaterialEnergy, MixturesConserveEnergy) {
  Pcg32 rng(5);
  for (const Case &c : cases()) {
    Material m = material(c.json);
    for (Vec3 wo : incident()) {
      Bsdf bsdf = m.make_bsdf(point(), wo);
      const int n = 60000;
      double sum = 0, sum2 = 0;
      for (int i = 0; i < n; ++i) {
        BsdfSample s;
        float ul = rng.next_float(), a = rng.next_float();
        double v = 0;
        if (bsdf.sample(wo, ul, {a, rng.next_float()}, TransportMode::Radiance, s)) v = max_component(s.weight);
        sum += v;
        sum2 += v * v;
      }
      double mean = sum / n, se = std::sqrt(std::max(0.0, sum2 / n - mean * mean) / n);
      if (!c.additive || wo.z >= 0.5f)
        EXPECT_LE(mean, 1.0 + 4 * se + 1e-4) << c.name << " wo.z=" << wo.z << " albedo " << mean;
      // Lossless within 1.5%; at 87 degrees 4%: a clearcoat over a glossy lobe takes
      // its layer albedo at the lobe's (grazing) outgoing directions, more than the
      // cosine-weighted normalisation assumes.
      if (c.lossless) EXPECT_NEAR(mean, 1.0, wo.z > 0.2f ? 0.015 : 0.04) << c.name << " wo.z=" << wo.z << " albedo " << mean;
    }
  }
}

TEST(MaterialParsing, PrincipledWarningsAndErrors) {
  Material m = material(R"({"type":"principled","subsurface":0.5,"clearcoat_normal":{"node":"bump","height":0.5}})");
  std::string all;
  for (auto &w : m.warnings) all += w + "\n";
  EXPECT_NE(all.find("subsurface"), std::string::npos) << all;
  EXPECT_NE(all.find("clearcoat_normal"), std::string::npos) << all;
  EXPECT_THROW(material(R"({"type":"principled","clearcoat":0.5,"coat_weight":0.5})"), Error);
  EXPECT_THROW(material(R"({"type":"principled","base_colour":[1,0,0]})"), Error);
  EXPECT_THROW(material(R"({"type":"mix","shader1":{"type":"diffuse","colr":1}})"), Error);
  // Emission on a principled and inside a mix is constant radiance for the lights.
  Material e = material(R"({"type":"mix","fac":0.25,"shader1":{"type":"emission","color":[1,1,1],"strength":4},"shader2":{"type":"diffuse"}})");
  EXPECT_NEAR(e.emission.x, 3.0f, 1e-6f);
  Material p = material(R"({"type":"principled","emission_color":[1,0.5,0],"emission_strength":2})");
  EXPECT_NEAR(p.emission.y, 1.0f, 1e-6f);
}

// Alpha: a half-transparent principled surface passes half the light straight through.
TEST(MaterialSampling, AlphaIsStraightTransmission) {
  Material m = material(R"({"type":"principled","alpha":0.25,"base_color":[1,1,1]})");
  Vec3 wo = normalize(Vec3(0.3f, 0.2f, 0.9f));
  Bsdf bsdf = m.make_bsdf(point(), wo);
  int through = 0, n = 4000;
  Pcg32 rng(9);
  for (int i = 0; i < n; ++i) {
    BsdfSample s;
    float ul = rng.next_float(), a = rng.next_float();
    if (!bsdf.sample(wo, ul, {a, rng.next_float()}, TransportMode::Radiance, s)) continue;
    if (s.is_delta && dot(s.wi, -wo) > 0.99999f) {
      ++through;
      EXPECT_NEAR(s.weight.x * s.pdf, 0.75f, 1e-4f);  // weight x selection probability = 1 - alpha
    }
  }
  EXPECT_GT(through, 0);
}

// Reciprocity of whole non-transmissive materials (shading normal = geometric normal):
// f(wo, wi) = f(wi, wo) for every lobe combination the Principled BSDF and mixes build.
TEST(MaterialReciprocity, NonTransmissiveMaterialsAreSymmetric) {
  Pcg32 rng(17);
  for (const char *json : {R"({"type":"principled","sheen":1,"clearcoat":1,"roughness":0.4,"metallic":0.3})",
                           R"({"type":"principled","base_color":[0.9,0.6,0.3],"metallic":1,"roughness":0.6,"distribution":"MULTI_GGX"})",
                           R"({"type":"mix","fac":0.4,"shader1":{"type":"diffuse","roughness":0.7},"shader2":{"type":"glossy","roughness":0.3}})"}) {
    Material m = material(json);
    Bsdf bsdf = m.make_bsdf(point(), Vec3(0, 0, 1));
    for (int i = 0; i < 2000; ++i) {
      Vec3 a = uniform_hemisphere_for_test(std::max(rng.next_float(), 1e-3f), rng.next_float());
      Vec3 b = uniform_hemisphere_for_test(std::max(rng.next_float(), 1e-3f), rng.next_float());
      Color fab = bsdf.eval(a, b, TransportMode::Radiance) / b.z, fba = bsdf.eval(b, a, TransportMode::Radiance) / a.z;
      for (int k = 0; k < 3; ++k) EXPECT_NEAR(fab[k], fba[k], 1e-3f * std::max(1.0f, fab[k])) << json;
    }
  }
}

// White furnace of a Mix Shader of two full Principled BSDFs (every lobe active: alpha's
// pass-through, diffuse with subsurface mixed in, sheen, specular, transmission,
// clearcoat; 12 lobes and 6 layers together): its directional albedo under a white sky
// is (1 - fac) x the first's + fac x the second's, each measured alone. Lobes dropped
// past a fixed capacity make the mix darker (before the fix: the second BSDF lost its
// sheen, specular, transmission and coat). The mix factor as a constant (lobes resolved
// when parsed) and as a texture of the same value (lobes built per hit). Per channel,
// 3 directions, 2 factors: 18 z-tests at |z| < 4.5 (false-alarm rate < 1.3e-4 for the
// test; fixed seeds).
TEST(MaterialEnergy, MixOfTwoFullPrincipledKeepsEveryLobe) {
  const std::string a = R"({"type":"principled","base_color":[1,1,1],"subsurface":0.3,"subsurface_color":[1,1,1],"specular":0.5,"roughness":0.3,"sheen":1,"sheen_tint":0.5,"clearcoat":1,"clearcoat_roughness":0.1,"transmission":0.4,"ior":1.45,"alpha":0.9})";
  const std::string b = R"({"type":"principled","base_color":[0.9,0.7,0.5],"subsurface":0.5,"subsurface_color":[0.8,0.9,1],"metallic":0.3,"specular":0.7,"specular_tint":0.3,"roughness":0.6,"sheen":0.8,"clearcoat":0.5,"clearcoat_roughness":0.3,"transmission":0.3,"transmission_roughness":0.2,"ior":1.3,"alpha":0.8})";
  const float fac = 0.35f;
  struct Albedo { Color mean, se; };
  // Directional albedo per channel: the mean sample weight (Radiance mode: flux).
  auto albedo = [](const Material &m, Vec3 wo, uint64_t seed) {
    Bsdf bsdf = m.make_bsdf(point(), wo);
    Pcg32 rng(seed);
    const int n = 200000;
    Color sum(0.0f);
    double s[3] = {0, 0, 0}, s2[3] = {0, 0, 0};
    for (int i = 0; i < n; ++i) {
      BsdfSample smp;
      float ul = rng.next_float(), u1 = rng.next_float();
      if (!bsdf.sample(wo, ul, {u1, rng.next_float()}, TransportMode::Radiance, smp)) continue;
      for (int k = 0; k < 3; ++k) { s[k] += smp.weight[k]; s2[k] += double(smp.weight[k]) * smp.weight[k]; }
    }
    Albedo r;
    for (int k = 0; k < 3; ++k) {
      double mean = s[k] / n;
      r.mean[k] = float(mean);
      r.se[k] = float(std::sqrt(std::max(0.0, s2[k] / n - mean * mean) / n));
    }
    return r;
  };
  Material ma = material(a.c_str()), mb = material(b.c_str());
  auto merge_warning = [](const Material &m) {
    for (const std::string &w : m.warnings)
      if (w.find("merged") != std::string::npos) return w;
    return std::string();
  };
  for (bool textured : {false, true}) {
    std::string f = textured ? R"({"node":"checker","color1":[0.35,0.35,0.35],"color2":[0.35,0.35,0.35]})" : "0.35";
    std::string mix = R"({"type":"mix","fac":)" + f + R"(,"shader1":)" + a + R"(,"shader2":)" + b + "}";
    Material m = material(mix.c_str());
    EXPECT_EQ(m.is_constant(), !textured);
    EXPECT_EQ(merge_warning(m), "");  // 12 lobes and 6 layers fit
    uint64_t seed = textured ? 1000 : 2000;
    for (Vec3 wo : incident()) {
      Albedo am = albedo(m, wo, seed++), aa = albedo(ma, wo, seed++), ab = albedo(mb, wo, seed++);
      for (int k = 0; k < 3; ++k) {
        double expected = (1 - fac) * aa.mean[k] + fac * ab.mean[k];
        double se = std::sqrt(sqr(am.se[k]) + sqr((1 - fac) * aa.se[k]) + sqr(fac * ab.se[k]));
        EXPECT_LT(std::fabs(am.mean[k] - expected), 4.5 * se)
            << (textured ? "textured" : "constant") << " factor, wo.z=" << wo.z << " channel " << k << ": mix albedo "
            << am.mean[k] << ", parts " << expected << " (+- " << se << ")";
      }
    }
  }
  // Past the capacity (a third Principled BSDF: 18 lobes, 9 layers): a warning naming
  // the material, and lobes merged so the albedo stays within 3% of the parts'.
  const std::string c = R"({"type":"principled","base_color":[0.4,0.8,0.6],"subsurface":0.3,"subsurface_color":[1,1,1],"specular":0.5,"roughness":0.45,"sheen":0.5,"clearcoat":0.8,"clearcoat_roughness":0.2,"transmission":0.5,"ior":1.6,"alpha":0.7})";
  std::string mix3 = R"({"type":"mix","fac":0.5,"shader1":{"type":"mix","fac":0.35,"shader1":)" + a + R"(,"shader2":)" + b +
                     R"(},"shader2":)" + c + "}";
  Params p(mix3, "material 'three_layers'");
  Material m3 = Material::from_params(p, "three_layers");
  std::string w = merge_warning(m3);
  EXPECT_NE(w.find("material 'three_layers'"), std::string::npos) << w;
  Material mc = material(c.c_str());
  uint64_t seed = 3000;
  for (Vec3 wo : incident()) {
    Albedo am = albedo(m3, wo, seed++), aa = albedo(ma, wo, seed++), ab = albedo(mb, wo, seed++), ac = albedo(mc, wo, seed++);
    for (int k = 0; k < 3; ++k) {
      double expected = 0.5 * ((1 - fac) * aa.mean[k] + fac * ab.mean[k]) + 0.5 * ac.mean[k];
      EXPECT_NEAR(am.mean[k], expected, 0.03 * expected) << "three Principled BSDFs, wo.z=" << wo.z << " channel " << k;
    }
  }
}

// The additive Principled BSDF's specular Fresnel is Cycles 3.4's (interpolate_fresnel_color):
// from its normal-incidence colour f0 to white as the dielectric Fresnel of the IOR Specular
// stands for, 2 / (1 - sqrt(0.08 specular)) - 1, runs from its own normal-incidence value to 1.
// Checked against that formula written out here (the Fresnel equations in double), and at
// Specular 0 on a black, non-metallic base: no reflection at all, even at grazing angles (with
// Schlick's (1 - cos)^5, which the lobe had before 2026-11-29, 42% of white at 81 degrees;
// a glossy Principled floor lit and seen at 9 degrees of elevation was 10.6 times Cycles' then,
// 1.20 now; with Specular 0.5, 1.083 then and 1.032 now). Deterministic.
TEST(MaterialFresnel, AdditiveSpecularIsCycles34s) {
  const auto dielectric = test::dielectric_fresnel;
  for (double specular : {0.2, 0.5, 1.0})
    for (double tint : {0.0, 0.5}) {
      const double ior = 2 / (1 - std::sqrt(0.08 * specular)) - 1, r0 = dielectric(1, ior);
      Lobe lobe;
      lobe.type = LobeType::GgxConductor;
      lobe.fresnel_mode = FresnelMode::Interpolated;
      lobe.ior = float(ior);
      lobe.f0 = Color(float(0.08 * specular), float(0.08 * specular * (1 - tint)), float(0.5 * tint));
      for (double cos_i : {1.0, 0.8, 0.5, 0.2, 0.05}) {
        const double fh = (dielectric(cos_i, ior) - r0) / (1 - r0);
        const Color f = lobe.fresnel(float(cos_i));
        for (int k = 0; k < 3; ++k)
          EXPECT_NEAR(f[k], lobe.f0[k] * (1 - fh) + fh, 2e-6) << "specular " << specular << " cos " << cos_i;
      }
    }
  const Material m = material(R"({"type":"principled","layering":"additive","base_color":[0,0,0],"specular":0,"roughness":0.35})");
  const Vec3 wo = normalize(Vec3(0, -1, 0.15f));
  const Bsdf bsdf = m.make_bsdf(point(), wo);
  for (Vec3 wi : {normalize(Vec3(0, 1, 0.15f)), normalize(Vec3(0.3f, 1, 0.4f)), Vec3(0, 0, 1)})
    EXPECT_TRUE(is_black(bsdf.eval(wo, wi, TransportMode::Radiance))) << "specular 0 reflects at " << wi.z;
}

// Blender 3.x materials ("microfacets": "cycles_3.4", which the add-on writes in Blender before
// 3.5) shadow every GGX lobe as Cycles 3.4 does, by Smith's separable G1(wo) G1(wi), not the
// height-correlated 1 / (1 + lambda_o + lambda_i) (Cycles 3.5 on; our default), and split rough
// glass as Cycles 3.4 does. A Glossy BSDF against Cycles 3.4's bsdf_microfacet_ggx_eval_reflect
// written out here in double (f cos_i = D G1o G1i / (4 cos_o)), at steep and grazing pairs of
// directions; rough glass, reflected and refracted, likewise. With the height-correlated form a
// Principled floor lit and seen at 9 degrees (roughness 0.8, black base) was 1.50 of Cycles'
// image (test blender.brightness.grazing_gloss). Deterministic.
TEST(MaterialMicrofacets, Cycles34LobesAreCycles34s) {
  auto tan2 = [](double c) { return (1 - c * c) / (c * c); };
  auto g1 = [&](double a2, double c) { return 2 / (1 + std::sqrt(1 + a2 * tan2(c))); };
  const Vec3 wos[] = {normalize(Vec3(0.2f, 0, 1)), normalize(Vec3(0.8f, 0.1f, 0.6f)), normalize(Vec3(0, -1, 0.156f))};
  const Vec3 wis[] = {normalize(Vec3(-0.3f, 0.1f, 1)), normalize(Vec3(-0.5f, 0.6f, 0.4f)), normalize(Vec3(0, 1, 0.156f)),
                      normalize(Vec3(0.1f, 1, 0.05f))};
  for (double r : {0.3, 0.6, 0.9}) {
    const double a2 = r * r * r * r;
    const std::string glossy = R"({"type":"glossy","color":[1,1,1],"roughness":)" + std::to_string(r) +
                               R"(,"microfacets":"cycles_3.4"})";
    const Bsdf bsdf = material(glossy.c_str()).make_bsdf(point(), wos[0]);
    for (Vec3 wo : wos)
      for (Vec3 wi : wis) {
        const Vec3 h = normalize(wo + wi);
        const double cos_m2 = double(h.z) * h.z;
        const double d = a2 / (kPi * cos_m2 * cos_m2 * sqr(a2 + tan2(h.z)));
        const double cycles = d * g1(a2, wo.z) * g1(a2, wi.z) / (4 * wo.z);
        const double ours = bsdf.eval(wo, wi, TransportMode::Radiance).x;
        EXPECT_NEAR(ours, cycles, 2e-4 * cycles) << "roughness " << r << " wo.z " << wo.z << " wi.z " << wi.z;
      }
    // Rough glass: Cycles 3.4's two closures, reflection weighted by the Fresnel of wo at the
    // shading normal (F = 1 per facet), refraction by 1 - that (bsdf_microfacet_ggx_eval_transmit:
    // G |cos_hi cos_ho| D eta^2 / (cos_o |eta wi + wo|^2), no Fresnel per facet). And the
    // Principled BSDF's glass: the same two closures, the refraction tinted by the base colour
    // and as rough as 1 - (1 - roughness)(1 - transmission roughness).
    const double eta = 1.45;
    auto reflect = [&](double a2r, Vec3 wo, Vec3 wi) {
      const Vec3 h = normalize(wo + wi);
      const double cos_m2 = double(h.z) * h.z;
      return a2r / (kPi * cos_m2 * cos_m2 * sqr(a2r + tan2(h.z))) * g1(a2r, wo.z) * g1(a2r, wi.z) / (4 * wo.z);
    };
    auto transmit = [&](double a2t, Vec3 wo, Vec3 wi) {
      const Vec3 ht = -(wi * float(eta) + wo), h = normalize(ht);
      const double cos_m2 = double(h.z) * h.z;
      const double d = a2t / (kPi * cos_m2 * cos_m2 * sqr(a2t + tan2(h.z)));
      return g1(a2t, wo.z) * g1(a2t, -wi.z) * std::fabs(dot(h, wi) * dot(h, wo)) * d * eta * eta / (wo.z * length_squared(ht));
    };
    const std::string glass = R"({"type":"glass","ior":1.45,"microfacets":"cycles_3.4","roughness":)" +
                              std::to_string(r) + "}";
    const std::string principled =
        R"({"type":"principled","layering":"additive","microfacets":"cycles_3.4","transmission":1,"ior":1.45,)"
        R"("base_color":[0.9,0.6,0.3],"transmission_roughness":0.3,"roughness":)" + std::to_string(r) + "}";
    const double rt = 1 - (1 - r) * 0.7, a2t = rt * rt * rt * rt;
    const Vec3 wo = wos[1], t = Vec3(-wo.x, -wo.y, 0) / 1.45f;
    const Vec3 refracted = t - Vec3(0, 0, std::sqrt(1 - length_squared(t)));
    const Bsdf bsdf_glass = material(glass.c_str()).make_bsdf(point(), wo);
    const Bsdf bsdf_principled = material(principled.c_str()).make_bsdf(point(), wo);
    // Specular Tint 0.5: the reflection's colour from base x 0.5 + 0.5 (green 0.8) at normal
    // incidence to white, by the facet's Fresnel normalised from its normal-incidence value
    // (interpolate_fresnel_color); the refraction as before.
    std::string tinted_json = principled;
    tinted_json.insert(tinted_json.size() - 1, R"(,"specular_tint":0.5)");
    const Bsdf bsdf_tinted = material(tinted_json.c_str()).make_bsdf(point(), wo);
    const double f0 = sqr((eta - 1) / (eta + 1));
    auto tint = [&](Vec3 wi) {
      const double fh = (test::dielectric_fresnel(dot(wo, normalize(wo + wi)), eta) - f0) / (1 - f0);
      return 0.8 * (1 - fh) + fh;
    };
    const double f_macro = test::dielectric_fresnel(wo.z, eta);
    for (Vec3 wi : {wis[0], wis[1], refracted, normalize(refracted + Vec3(0.15f, -0.1f, 0)),
                    normalize(refracted + Vec3(-0.2f, 0.1f, 0.1f))}) {
      const bool up = wi.z > 0;
      const double cycles = up ? f_macro * reflect(a2, wo, wi) : (1 - f_macro) * transmit(a2, wo, wi);
      const double ours = bsdf_glass.eval(wo, wi, TransportMode::Radiance).x;
      EXPECT_NEAR(ours, cycles, 2e-4 * cycles) << "glass, roughness " << r << " wi.z " << wi.z;
      const double cycles_p = up ? f_macro * reflect(a2, wo, wi) : 0.6 * (1 - f_macro) * transmit(a2t, wo, wi);
      const double ours_p = bsdf_principled.eval(wo, wi, TransportMode::Radiance).y;
      EXPECT_NEAR(ours_p, cycles_p, 2e-4 * cycles_p) << "Principled glass, roughness " << r << " wi.z " << wi.z;
      const double cycles_t = up ? cycles_p * tint(wi) : cycles_p;
      const double ours_t = bsdf_tinted.eval(wo, wi, TransportMode::Radiance).y;
      EXPECT_NEAR(ours_t, cycles_t, 2e-4 * cycles_t) << "tinted Principled glass, roughness " << r << " wi.z " << wi.z;
    }
  }
}

}  // namespace test_material_principled
