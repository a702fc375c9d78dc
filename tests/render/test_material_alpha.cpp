// Transparent shadows: sunlight reaching a white floor through a partly transparent
// quad (Principled alpha; a Transparent BSDF in a mix) is scaled by what passes
// straight through, as Cycles' transparent shadows; an opaque quad blocks it.
// Direct light only (max_bounces 1, a delta sun): the expected radiance is exact.
// z-test on the pixel mean at |z| < 4.5 with a 1e-4 relative allowance; fixed seeds.
#include <gtest/gtest.h>
#include <cmath>
#include <nlohmann/json.hpp>
#include "render_helpers.h"

namespace test_material_alpha {

using namespace rdv::test;
using nlohmann::json;

namespace {

Image floor_under(const json &occluder, const char *integrator = "path") {
  json mats = json::array({{{"name", "floor"}, {"type", "diffuse"}, {"color", {1, 1, 1}}}});
  json occ = occluder;
  occ["name"] = "occluder";
  mats.push_back(occ);
  json j = {{"settings", {{"width", 8}, {"height", 8}, {"samples", 16}, {"max_bounces", 1}, {"integrator", integrator}}},
            {"camera", {{"type", "orthographic"}, {"ortho_scale", 0.2}, {"clip_start", 0.01},
                        {"transform", {{"look_at", {{"from", {0, 0.001, 3}}, {"to", {0, 0, 0}}}}}}}},
            {"world", {{"color", {0, 0, 0}}}},
            {"materials", mats},
            {"meshes", {{{"name", "floor"}, {"shape", {{"type", "quad"}, {"size", 4}}}, {"materials", {"floor"}}},
                        {{"name", "card"}, {"shape", {{"type", "quad"}, {"size", 1}}}, {"materials", {"occluder"}},
                         {"transform", {{"translate", {1, 0, 1}}}}}}},
            {"lights", {{{"type", "sun"}, {"strength", 3}, {"angle", 0}, {"direction", {-1, 0, -1}}}}}};
  return render_json(j.dump());
}

void expect_mean(const Image &img, const double expected[3], const char *what) {
  ASSERT_TRUE(img.all_finite()) << what;
  for (int c = 0; c < 3; ++c) {
    MeanEstimate m = pixel_mean(img, c);
    double z = (m.mean - expected[c]) / std::hypot(m.standard_error, 1e-4 * std::max(expected[c], 1e-3));
    EXPECT_LT(std::fabs(z), 4.5) << what << " channel " << c << ": " << m.mean << " expected " << expected[c];
  }
}

}  // namespace

TEST(TransparentShadows, AlphaAndTransparentBsdfTintTheSun) {
  const double lit = 3.0 * std::cos(M_PI / 4) / M_PI;  // E cos(45 deg) / pi, albedo 1
  const double none[3] = {0, 0, 0};
  expect_mean(floor_under({{"type", "diffuse"}}), none, "opaque card");
  const double alpha[3] = {0.75 * lit, 0.75 * lit, 0.75 * lit};
  expect_mean(floor_under({{"type", "principled"}, {"alpha", 0.25}}), alpha, "principled alpha 0.25");
  const double mix[3] = {0.6 * lit, 0.3 * lit, 0.15 * lit};
  expect_mean(floor_under({{"type", "mix"}, {"fac", 0.6}, {"shader1", {{"type", "diffuse"}}},
                           {"shader2", {{"type", "transparent"}, {"color", {1, 0.5, 0.25}}}}}),
              mix, "60% transparent BSDF");
  const double full[3] = {lit, lit, lit};
  expect_mean(floor_under({{"type", "transparent"}}), full, "fully transparent card");
}

// BDPT passes plain transparent layers without making them path vertices and its
// connections see through them (bdpt/subpaths.cpp), so next-event estimation reaches the
// sun behind the card as the path tracer's does: with an orthographic camera no other
// strategy can (light tracing cannot reach it), and before, BDPT left the floor black.
TEST(TransparentShadows, BdptSeesTheSunThroughCardsAsThePathTracerDoes) {
  const double lit = 3.0 * std::cos(M_PI / 4) / M_PI;
  const double none[3] = {0, 0, 0};
  expect_mean(floor_under({{"type", "diffuse"}}, "bdpt"), none, "bdpt, opaque card");
  const double alpha[3] = {0.75 * lit, 0.75 * lit, 0.75 * lit};
  expect_mean(floor_under({{"type", "principled"}, {"alpha", 0.25}}, "bdpt"), alpha, "bdpt, principled alpha 0.25");
  const double mix[3] = {0.6 * lit, 0.3 * lit, 0.15 * lit};
  expect_mean(floor_under({{"type", "mix"}, {"fac", 0.6}, {"shader1", {{"type", "diffuse"}}},
                           {"shader2", {{"type", "transparent"}, {"color", {1, 0.5, 0.25}}}}},
                          "bdpt"),
              mix, "bdpt, 60% transparent BSDF");
  const double full[3] = {lit, lit, lit};
  expect_mean(floor_under({{"type", "transparent"}}, "bdpt"), full, "bdpt, fully transparent card");
}

}  // namespace test_material_alpha
