// Mix Shader factors by the viewing direction (Cycles' Fresnel and Layer Weight nodes,
// bsdfs/view_factor.h): their values are Cycles' formulas, a Bsdf applies them at each pair's
// camera-side direction whichever way it was built (so a light path sees what a camera path
// sees: one f and one density per pair of directions), and what the engine cannot follow by
// direction falls back to the factor's mean with a warning. The sampling, weight and energy
// checks of these materials are the whole-material cases of test_material_principled.cpp.
// Deterministic: fixed seeds, tolerances of float rounding.
#include <gtest/gtest.h>
#include <limits>
#include "bsdfs/material.h"
#include "test_materials.h"
#include "fresnel_reference.h"
#include "core/hash.h"

namespace test_material_view_factors {

using namespace rdv;

namespace {

Material material(const std::string &json) { return test::material_from_json(json); }
ShadingPoint point(Vec3 ns = Vec3(0, 0, 1)) { return test::flat_point(ns); }

Vec3 direction(Pcg32 &rng, bool upper) {
  const float z = std::max(rng.next_float(), 1e-3f), phi = 2 * kPi * rng.next_float();
  const float r = std::sqrt(std::max(0.0f, 1 - z * z));
  return Vec3(r * std::cos(phi), r * std::sin(phi), upper ? z : -z);
}

std::string all_warnings(const Material &m) {
  std::string all;
  for (const std::string &w : m.warnings) all += w + "\n";
  return all;
}

}  // namespace

// The factors against Cycles 3.4's svm_node_fresnel / svm_node_layer_weight written out in
// double: Fresnel of IOR eta (1 / eta seen from behind the front face), Layer Weight's
// Fresnel of IOR 1 / (1 - blend) (inverted likewise), Facing 1 - |cos|^b with b = 2 blend
// below a half and 0.5 / (1 - blend) above.
TEST(ViewFactors, AreCyclesFormulas) {
  const Vec3 n(0, 0, 1), front(0, 0, 1);
  for (float c : {1.0f, 0.8f, 0.5f, 0.2f, 0.05f})
    for (float side : {1.0f, -1.0f}) {
      const Vec3 w(std::sqrt(1 - c * c), 0, side * c);
      auto at = [&](ViewFactorKind kind, float param) { return ViewFactor{kind, param}.at(w, n, front); };
      for (float ior : {1.1f, 1.45f, 2.4f}) {
        const double eta = side > 0 ? ior : 1.0 / ior;
        EXPECT_NEAR(at(ViewFactorKind::Fresnel, ior), test::dielectric_fresnel(c, eta), 2e-6) << c << " " << ior;
      }
      for (float blend : {0.1f, 0.3f, 0.5f, 0.7f, 0.95f}) {
        const double eta = side > 0 ? 1.0 / (1.0 - blend) : 1.0 - blend;
        EXPECT_NEAR(at(ViewFactorKind::LayerFresnel, blend), test::dielectric_fresnel(c, eta), 2e-6)
            << c << " " << blend;
        const double b = blend < 0.5 ? 2.0 * blend : 0.5 / (1.0 - blend);
        EXPECT_NEAR(at(ViewFactorKind::LayerFacing, blend), 1.0 - std::pow(c, b), 2e-6)
            << c << " " << blend;
      }
    }
  // Degenerate inputs stay in [0, 1].
  for (float p : {0.0f, -1.0f, 1.0f, 1e30f, std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity()}) {
    for (ViewFactorKind k : {ViewFactorKind::Fresnel, ViewFactorKind::LayerFresnel, ViewFactorKind::LayerFacing}) {
      const float v = ViewFactor{k, p}.at(normalize(Vec3(0.3f, 0, 0.7f)), n, front);
      EXPECT_TRUE(v >= 0 && v <= 1) << int(k) << " " << p << " -> " << v;
    }
  }
}

// A white diffuse closure under a Fresnel factor (the mix's first shader, 1 - F): f = (1 -
// F(|w . N|)) / pi with w the camera-side direction and N the interpolated normal, here tilted
// from the geometric one (the frame's, too). Camera paths (Radiance) take wo, light paths
// (Importance) wi; the shading-normal correction of light paths is Veach's, as for any lobe.
TEST(ViewFactors, WeightIsTakenAtTheCameraSideDirection) {
  const Vec3 ns = normalize(Vec3(0.2f, -0.1f, 1.0f));
  Material m = material(R"({"type":"mix","fac":{"node":"fresnel","ior":1.6},"shader1":{"type":"diffuse","color":[1,1,1]}})");
  ASSERT_FALSE(m.is_constant());
  Pcg32 rng(41);
  int checked = 0;
  for (int i = 0; i < 400; ++i) {
    const Vec3 wo = direction(rng, true), wi = direction(rng, true);
    if (dot(wo, ns) <= 0.05f || dot(wi, ns) <= 0.05f) continue;
    const Bsdf bsdf = m.make_bsdf(point(ns), wo);
    const double expect_r = (1 - test::dielectric_fresnel(std::fabs(dot(wo, ns)), 1.6)) / kPi;
    EXPECT_NEAR(bsdf.f(wo, wi, TransportMode::Radiance).x, expect_r, 2e-6);
    const double correction = std::fabs(dot(wo, ns)) * wi.z / (wo.z * std::fabs(dot(wi, ns)));
    const double expect_i = (1 - test::dielectric_fresnel(std::fabs(dot(wi, ns)), 1.6)) / kPi * correction;
    EXPECT_NEAR(bsdf.f(wo, wi, TransportMode::Importance).x, expect_i, 2e-6 * std::max(1.0, expect_i));
    ++checked;
  }
  EXPECT_GT(checked, 200);
  // From behind the front face the IOR is inverted (Cycles' back-facing flag).
  const Vec3 wo(0.6f, 0, -0.8f), wi(-0.3f, 0.1f, -0.9f);
  const Bsdf back = m.make_bsdf(point(), normalize(wo));
  EXPECT_NEAR(back.f(normalize(wo), normalize(wi), TransportMode::Radiance).x, (1 - test::dielectric_fresnel(0.8, 1 / 1.6)) / kPi, 2e-6);
}

// Nodes between the factor and the Mix Shader, baked by the exporter into a table over the
// factor's [0, 1]: read linearly. Facing at blend 0.5 is 1 - cos; the table [1, 0] makes it cos,
// so a white diffuse as the mix's second shader reflects cos / pi; a three-entry table bends it.
TEST(ViewFactors, TableMapsTheFactor) {
  Material inverted = material(
      R"({"type":"mix","fac":{"node":"layer_weight","output":"facing","table":[1,0]},"shader2":{"type":"diffuse","color":[1,1,1]}})");
  Material bent = material(
      R"({"type":"mix","fac":{"node":"layer_weight","output":"facing","table":[0,0.8,1]},"shader2":{"type":"diffuse","color":[1,1,1]}})");
  const Vec3 wi = normalize(Vec3(-0.2f, 0.1f, 0.9f));
  for (float c : {0.95f, 0.6f, 0.3f, 0.1f}) {
    const Vec3 wo(std::sqrt(1 - c * c), 0, c);
    EXPECT_NEAR(inverted.make_bsdf(point(), wo).f(wo, wi, TransportMode::Radiance).x, c / kPi, 2e-6) << c;
    const float x = 1 - c, g = x < 0.5f ? 1.6f * x : 0.8f + 0.4f * (x - 0.5f);
    EXPECT_NEAR(bent.make_bsdf(point(), wo).f(wo, wi, TransportMode::Radiance).x, g / kPi, 2e-6) << c;
  }
  EXPECT_THROW(material(R"({"type":"mix","fac":{"node":"fresnel","table":[0.5]},"shader1":{"type":"diffuse"}})"), Error);
  EXPECT_THROW(material(R"({"type":"mix","fac":{"node":"fresnel","table":[0,"a"]},"shader1":{"type":"diffuse"}})"), Error);
}

// Geometry > Backfacing as a Mix Shader's factor: a two-sided surface (green in front, red
// behind), the side taken from the camera-side direction, so a light path reaching the back
// from the front's side of a pair still sees what the camera sees.
TEST(ViewFactors, BackfacingMakesTwoSidedSurfaces) {
  Material two_sided = material(
      R"({"type":"mix","fac":{"node":"backfacing"},"shader1":{"type":"diffuse","color":[0,1,0]},"shader2":{"type":"diffuse","color":[1,0,0]}})");
  Pcg32 rng(5);
  for (int i = 0; i < 200; ++i) {
    const bool back = (i & 1) != 0;
    const Vec3 c = direction(rng, !back), l = direction(rng, !back);
    const Bsdf from_camera = two_sided.make_bsdf(point(), c), from_light = two_sided.make_bsdf(point(), l);
    const Color f = from_camera.f(c, l, TransportMode::Radiance);
    EXPECT_NEAR(f.x, back ? kInvPi : 0.0f, 1e-6f);
    EXPECT_NEAR(f.y, back ? 0.0f : kInvPi, 1e-6f);
    const Color f_light = from_light.f(l, c, TransportMode::Importance);
    EXPECT_NEAR(f_light.x, f.x, 1e-6f);
    EXPECT_NEAR(f_light.y, f.y, 1e-6f);
  }
  const ViewFactor backfacing{ViewFactorKind::Backfacing, 0};
  EXPECT_EQ(backfacing.at(Vec3(0, 0, -1), Vec3(0, 0, 1), Vec3(0, 0, 1)), 1.0f);
  EXPECT_EQ(backfacing.at(Vec3(0, 0, 1), Vec3(0, 0, 1), Vec3(0, 0, 1)), 0.0f);
}

// The same pair of directions gives one f and one pair of densities whichever direction the
// Bsdf was built toward: a camera path reaching the surface from c and a light path reaching it
// from l (BDPT's connections and its MIS, light tracing, path-space MLT). With the factors taken
// at the direction the Bsdf was built toward, the first check fails (the light path's f would
// use F(l)).
TEST(ViewFactors, LightPathsSeeWhatCameraPathsSee) {
  const char *reflecting[] = {
      R"({"type":"mix","fac":{"node":"fresnel","ior":1.45},"shader1":{"type":"diffuse","color":[0.8,0.3,0.2]},"shader2":{"type":"glossy","roughness":0.2}})",
      R"({"type":"mix","fac":{"node":"layer_weight","output":"facing","blend":0.7},"shader1":{"type":"mix","fac":{"node":"fresnel","ior":1.3},"shader1":{"type":"diffuse"},"shader2":{"type":"principled","roughness":0.4}},"shader2":{"type":"glossy","roughness":0.05}})",
      R"({"type":"mix","fac":{"node":"layer_weight","blend":0.4},"shader1":{"type":"diffuse"},"shader2":{"type":"glossy","roughness":0.5,"color":{"node":"checker","scale":3}}})"};
  const char *transmitting =
      R"({"type":"mix","fac":{"node":"layer_weight","output":"facing","blend":0.3},"shader1":{"type":"diffuse"},"shader2":{"type":"glass","roughness":0.3,"ior":1.5}})";
  Pcg32 rng(7);
  for (const char *json : reflecting) {
    Material m = material(json);
    for (int i = 0; i < 500; ++i) {
      const Vec3 c = direction(rng, true), l = direction(rng, true);
      const Bsdf from_camera = m.make_bsdf(point(), c), from_light = m.make_bsdf(point(), l);
      const Color f_camera = from_camera.f(c, l, TransportMode::Radiance);
      const Color f_light = from_light.f(l, c, TransportMode::Importance);
      for (int k = 0; k < 3; ++k) EXPECT_NEAR(f_light[k], f_camera[k], 1e-5f * std::max(1.0f, f_camera[k])) << json;
      float fwd, rev;
      const Color f_both = from_light.f_and_pdfs(l, c, TransportMode::Importance, fwd, rev);
      EXPECT_NEAR(f_both.x, f_camera.x, 1e-5f * std::max(1.0f, f_camera.x)) << json;
      EXPECT_NEAR(fwd, from_camera.pdf(l, c), 1e-5f * std::max(1.0f, fwd)) << json;
      EXPECT_NEAR(rev, from_camera.pdf(c, l), 1e-5f * std::max(1.0f, rev)) << json;
    }
  }
  // Through glass f differs by the transport mode (1 / eta^2); the densities may not.
  Material glass = material(transmitting);
  for (int i = 0; i < 500; ++i) {
    const Vec3 c = direction(rng, true), l = direction(rng, (i & 1) != 0);
    const Bsdf from_camera = glass.make_bsdf(point(), c), from_light = glass.make_bsdf(point(), l);
    EXPECT_NEAR(from_light.pdf(c, l), from_camera.pdf(c, l), 1e-5f * std::max(1.0f, from_camera.pdf(c, l)));
    EXPECT_NEAR(from_light.pdf(l, c), from_camera.pdf(l, c), 1e-5f * std::max(1.0f, from_camera.pdf(l, c)));
  }
}

// What the engine does not follow by direction takes the factor's mean, with a warning naming
// the material; a view node where a colour goes, or an unknown output, is refused by name.
TEST(ViewFactors, FallbacksAndBadInput) {
  // Over an emission: emission x (1 - mean) in the constant emission, the diffuse beside it exact.
  Material e = material(
      R"({"type":"mix","fac":{"node":"fresnel","ior":1.45},"shader1":{"type":"emission","strength":2},"shader2":{"type":"diffuse"}})");
  const float mean = ViewFactor{ViewFactorKind::Fresnel, 1.45f}.cosine_weighted_mean();
  EXPECT_GT(mean, 0.05f);
  EXPECT_LT(mean, 0.15f);
  EXPECT_NEAR(e.emission.x, 2 * (1 - mean), 1e-5f);
  EXPECT_NE(all_warnings(e).find("emission under a view-dependent factor"), std::string::npos) << all_warnings(e);
  EXPECT_NE(all_warnings(e).find("material 'test'"), std::string::npos) << all_warnings(e);
  // Over transparency (a Transparent closure, Principled alpha) or a holdout: the mean.
  for (const char *json :
       {R"({"type":"mix","fac":{"node":"layer_weight","output":"facing"},"shader1":{"type":"transparent"},"shader2":{"type":"diffuse"}})",
        R"({"type":"mix","fac":{"node":"fresnel"},"shader1":{"type":"principled","alpha":0.5},"shader2":{"type":"glossy"}})",
        R"({"type":"mix","fac":{"node":"backfacing"},"shader1":{"type":"holdout"},"shader2":{"type":"diffuse"}})"}) {
    Material m = material(json);
    EXPECT_NE(all_warnings(m).find("transparency or a holdout"), std::string::npos) << json << "\n" << all_warnings(m);
  }
  // Beside them (a leaf: alpha around a two-sided mix) the factor stays exact: no warning.
  Material leaf = material(
      R"({"type":"mix","fac":0.3,"shader1":{"type":"transparent"},"shader2":{"type":"mix","fac":{"node":"backfacing"},"shader1":{"type":"diffuse","color":[0,1,0]},"shader2":{"type":"diffuse","color":[1,0,0]}}})");
  EXPECT_EQ(all_warnings(leaf).find("transparency or a holdout"), std::string::npos) << all_warnings(leaf);
  EXPECT_FALSE(leaf.is_constant());
  // More than four in one material: the fifth is its mean.
  std::string nested = R"({"type":"diffuse"})";
  for (int i = 0; i < 5; ++i)
    nested = R"({"type":"mix","fac":{"node":"fresnel","ior":)" + std::to_string(1.2 + 0.1 * i) + R"(},"shader1":)" +
             nested + R"(,"shader2":{"type":"glossy"}})";
  Material five = material(nested);
  EXPECT_NE(all_warnings(five).find("more than 4"), std::string::npos) << all_warnings(five);
  Bsdf bsdf = five.make_bsdf(point(), Vec3(0, 0, 1));
  EXPECT_TRUE(std::isfinite(bsdf.f(Vec3(0, 0, 1), normalize(Vec3(0.3f, 0.2f, 0.8f)), TransportMode::Radiance).x));
  // A Normal input: approximated, said.
  Material normal = material(
      R"({"type":"mix","fac":{"node":"fresnel","normal":{"node":"bump","height":0.5}},"shader1":{"type":"diffuse"},"shader2":{"type":"glossy"}})");
  EXPECT_NE(all_warnings(normal).find("Normal input"), std::string::npos) << all_warnings(normal);
  // Refused, naming the key.
  try {
    material(R"({"type":"diffuse","color":{"node":"fresnel"}})");
    ADD_FAILURE() << "a fresnel colour was accepted";
  } catch (const Error &err) {
    EXPECT_NE(std::string(err.what()).find("'color'"), std::string::npos) << err.what();
    EXPECT_NE(std::string(err.what()).find("mix's 'fac'"), std::string::npos) << err.what();
  }
  EXPECT_THROW(material(R"({"type":"mix","fac":{"node":"layer_weight","output":"rim"},"shader1":{"type":"diffuse"}})"), Error);
  EXPECT_THROW(material(R"({"type":"mix","fac":{"node":"fresnel","iorr":1.5},"shader1":{"type":"diffuse"}})"), Error);
}

}  // namespace test_material_view_factors
