// Glass end to end through the C ABI and the path tracer: a closed lossless
// dielectric sphere under a uniform world looks exactly like the world, whatever its
// IOR and roughness. This fails if refraction is blocked, if ray origins are offset
// to the wrong side, if refraction scales radiance at all in Radiance mode (Cycles'
// convention, bsdfs/dielectric.cpp), or if total internal reflection loses energy.
// z-test on the pixel mean at |z| < 4.5 (false-alarm rate < 1e-5 per check), fixed seeds.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include "render_helpers.h"

namespace test_material_glass {

using namespace rdv::test;
using nlohmann::json;

namespace {

std::string glass_furnace(double ior, double roughness, bool smooth_normals) {
  json j = {{"settings", {{"width", 16}, {"height", 16}, {"samples", 64}, {"max_bounces", 1000}}},
            {"camera", {{"type", "perspective"}, {"focal_length", 100},
                        {"transform", {{"look_at", {{"from", {0, -4, 0}}, {"to", {0, 0, 0}}}}}}}},
            {"world", {{"color", {0.8, 0.8, 0.8}}}},
            {"materials", {{{"name", "glass"}, {"type", "glass"}, {"color", {1, 1, 1}}, {"ior", ior}, {"roughness", roughness}}}},
            {"meshes", {{{"name", "ball"}, {"shape", {{"type", "sphere"}, {"radius", 1}, {"segments", 32}, {"smooth", smooth_normals}}},
                         {"materials", {"glass"}}}}}};
  return j.dump();
}

void expect_mean(const Image &img, double expected, const std::string &what, double rel_allowance = 1e-5) {
  ASSERT_TRUE(img.all_finite()) << what;
  for (int c = 0; c < 3; ++c) {
    MeanEstimate m = pixel_mean(img, c);
    double z = (m.mean - expected) / std::hypot(m.standard_error, rel_allowance * expected);
    EXPECT_LT(std::fabs(z), 4.5) << what << ": mean " << m.mean << " expected " << expected << " (se " << m.standard_error << ")";
  }
}

}  // namespace

TEST(GlassFurnace, SmoothSphereLooksLikeTheWorld) {
  // IOR 2.4: the flat facets trap rays by total internal reflection (critical angle
  // 24.6 degrees) until Russian roulette ends them, and the few survivors carry large
  // weights: a heavy tail that makes one image's mean typically low and its standard
  // error an underestimate (8 seeds at 256 spp: 0.786 .. 0.804, median 0.793, with or
  // without refraction's eta^2 in Radiance mode; 0.80 over seeds). Allowed 2% there.
  // IOR 4: heavier still; covered in stat tests.
  for (double ior : {1.0001, 1.5, 2.4})
    expect_mean(render_json(glass_furnace(ior, 0.0, false)), 0.8, "smooth glass ior " + std::to_string(ior),
                ior > 2 ? 0.02 : 1e-5);
}

TEST(GlassFurnace, RoughSphereLooksLikeTheWorld) {
  // Single-scattering GGX loses the energy of facet-to-facet bounces (as Cycles' plain
  // GGX glass does): at roughness 0.3 that is below 1% here; allow 2%.
  for (double ior : {1.33, 1.5})
    expect_mean(render_json(glass_furnace(ior, 0.3, false)), 0.8, "rough glass ior " + std::to_string(ior), 0.02);
}

TEST(GlassFurnace, SmoothNormalsDoNotLeakOrDarkenMuch) {
  // Smooth (interpolated) normals on a 32-segment sphere: directions on which the
  // geometric and shading normals disagree are dropped, costing a little energy at
  // silhouettes; never more light than the world.
  Image img = render_json(glass_furnace(1.5, 0.0, true));
  ASSERT_TRUE(img.all_finite());
  MeanEstimate m = pixel_mean(img, 1);
  EXPECT_LT(m.mean, 0.8 + 4.5 * m.standard_error + 1e-4);
  EXPECT_GT(m.mean, 0.8 * 0.95);
}

}  // namespace test_material_glass
