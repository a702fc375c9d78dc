// Scenes with closed-form answers, rendered end to end through the C ABI.
// Each check is a z-test on the mean over pixels (independent estimates) at |z| < 4.5:
// a false-alarm rate below 1e-5 per check; seeds are fixed, so verdicts are reproducible.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include "render_helpers.h"

namespace test_analytic_scenes {

using namespace rdv::test;
using nlohmann::json;

namespace {

// Camera at the centre of a closed sphere, flat-shaded: the emitting-shell answer
// holds for any closed shape; the point-light answer needs a fine tessellation.
std::string furnace_scene(double albedo, double emission, const std::string &extra_light = "", int segments = 24) {
  json j = {
      {"settings", {{"width", 16}, {"height", 16}, {"samples", 64}, {"max_bounces", 1000}}},
      {"camera", {{"type", "perspective"}, {"focal_length", 20}, {"transform", {{"look_at", {{"from", {0, 0, 0}}, {"to", {1, 0.3, 0.2}}}}}}}},
      {"world", {{"color", {0, 0, 0}}}},
      {"materials", {{{"name", "shell"}, {"type", "diffuse"}, {"color", {albedo, albedo, albedo}},
                      {"emission", {emission, emission, emission}}}}},
      {"meshes", {{{"name", "sphere"}, {"shape", {{"type", "sphere"}, {"radius", 1}, {"segments", segments}, {"smooth", false}}},
                   {"materials", {"shell"}}}}}};
  if (!extra_light.empty()) j["lights"] = json::array({json::parse(extra_light)});
  return j.dump();
}

void expect_mean(const Image &img, double expected, const char *what) {
  ASSERT_TRUE(img.all_finite()) << what;
  EXPECT_EQ(img.progress.samples_dropped, 0u) << what;
  for (int c = 0; c < 3; ++c) {
    MeanEstimate m = pixel_mean(img, c);
    // Plus a 1e-5 relative allowance for float rounding in noise-free cases.
    double z = (m.mean - expected) / std::hypot(m.standard_error, 1e-5 * expected);
    EXPECT_LT(std::fabs(z), 4.5) << what << ": mean " << m.mean << " expected " << expected << " (se " << m.standard_error << ")";
  }
}

}  // namespace

// Inside a closed sphere of albedo a emitting Le everywhere: L = Le / (1 - a).
TEST(WhiteFurnace, ClosedEmittingSphere) {
  expect_mean(render_json(furnace_scene(0.5, 1.0)), 1.0 / (1 - 0.5), "albedo 0.5");
  expect_mean(render_json(furnace_scene(0.9, 0.2)), 0.2 / (1 - 0.9), "albedo 0.9");
  expect_mean(render_json(furnace_scene(0.0, 0.7)), 0.7, "albedo 0");
}

// pbrt's classic: a point light of intensity pi (power 4 pi^2 W) at the centre of a
// unit sphere of reflectance 0.5: radiance 1 everywhere.
TEST(WhiteFurnace, PointLightInDiffuseSphere) {
  double power = 4 * M_PI * M_PI;
  std::string light = json{{"type", "point"}, {"position", {0, 0, 0}}, {"radius", 0}, {"power", power}}.dump();
  // 256 segments: the facets lie within 1e-4 of the unit sphere.
  expect_mean(render_json(furnace_scene(0.5, 0.0, light, 256)), 1.0, "point light in sphere");
}

// A white (albedo 1) diffuse sphere under a uniform world of radiance 0.8 looks like
// the world: 0.8 everywhere, however many bounces it takes.
TEST(WhiteFurnace, WhiteSphereUnderUniformWorld) {
  json j = {{"settings", {{"width", 16}, {"height", 16}, {"samples", 64}, {"max_bounces", 1000}}},
            {"camera", {{"type", "perspective"}, {"transform", {{"look_at", {{"from", {0, -4, 0}}, {"to", {0, 0, 0}}}}}}}},
            {"world", {{"color", {0.8, 0.8, 0.8}}}},
            {"materials", {{{"name", "white"}, {"type", "diffuse"}, {"color", {1, 1, 1}}}}},
            {"meshes", {{{"name", "ball"}, {"shape", {{"type", "sphere"}, {"radius", 1}, {"smooth", false}}}, {"materials", {"white"}}}}}};
  expect_mean(render_json(j.dump()), 0.8, "white sphere in uniform world");
}

// A white diffuse floor seen from straight above through a tiny orthographic window
// at the origin: radiance = E / pi, with E the light's closed-form irradiance.
TEST(LightUnits, RenderedFloorRadiance) {
  auto floor_with = [](const std::string &light) {
    json j = {{"settings", {{"width", 8}, {"height", 8}, {"samples", 256}, {"max_bounces", 1}}},
              {"camera", {{"type", "orthographic"}, {"ortho_scale", 0.002}, {"clip_start", 0.01},
                          {"transform", {{"look_at", {{"from", {0, 0.0005, 3}}, {"to", {0, 0, 0}}}}}}}},
              {"world", {{"color", {0, 0, 0}}}},
              {"materials", {{{"name", "white"}, {"type", "diffuse"}, {"color", {1, 1, 1}}}}},
              {"meshes", {{{"name", "floor"}, {"shape", {{"type", "quad"}, {"size", 0.01}}}, {"materials", {"white"}}}}},
              {"lights", json::array({json::parse(light)})}};
    return j.dump();
  };
  const double pi = M_PI, d = 2.0;
  expect_mean(render_json(floor_with(R"({"type":"point","position":[0,0,2],"radius":0,"power":100})")),
              100 / (4 * pi * d * d) / pi, "point light");
  expect_mean(render_json(floor_with(R"({"type":"sun","direction":[0,0,-1],"angle":0,"strength":2})")), 2 / pi,
              "sun");
  double R = 0.75, L = 100 / (4 * pi * R * R);
  expect_mean(render_json(floor_with(R"({"type":"area","position":[0,0,2],"direction":[0,0,-1],"shape":"disk","size":1.5,"power":100})")),
              L * R * R / (R * R + d * d), "disk area light");
}

}  // namespace test_analytic_scenes
