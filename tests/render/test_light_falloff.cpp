// Light Falloff (Blender's node; Cycles' svm_node_light_falloff): Strength times the length d of
// the ray the emitted light travels, to the power 0 (Quadratic), 1 (Linear) or 2 (Constant),
// times d^2 / (Smooth + d^2) when Smooth > 0. The engine passes d wherever emission is evaluated.
//  - A point lamp (radius 0) over a white floor, its Strength through each output: the floor's
//    radiance seen straight down has the closed form rho / pi x I f(d) cos / d^2; path tracing
//    and BDPT give it within 1e-3 (a delta lamp lighting a 2 cm view: every sample alike);
//    and at millimetres, and at kilometres 1,000 km from the origin, within 2e-3.
//  - scenes/light_falloff.json (a sphere lamp Linear, an area lamp Quadratic with Smooth, an
//    emissive panel Constant): next-event estimation, rays that meet the lamps and the panel,
//    and BDPT's light subpaths, whose first segment's length is known only once traced: path
//    tracing and BDPT give the same image (Welch's t-test per 8x8 block, 1% false-alarm rate
//    for the file, Sidak-corrected per block) and the same mean (|z| < 3.3: 1e-3). The
//    Metropolis integrators: MltVsBdpt.LightFalloff (test_mlt.cpp).
#include <gtest/gtest.h>
#include <cmath>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include "render_helpers.h"
#include "statistics.h"

namespace test_light_falloff {

using namespace rdv::test;
using nlohmann::json;

namespace {

// A 100 W point lamp `scale` metres above a white floor, seen straight down at (0.75, 0, 0)
// x scale, everything moved by `offset` along x.
json floor_under_point_lamp(const json &strength, double scale = 1, double offset = 0) {
  json cam = {{"type", "orthographic"}, {"ortho_scale", 0.02 * scale}, {"clip_start", 0.001 * scale},
              {"transform", {{"look_at", {{"from", {offset + 0.75 * scale, 0, 0.5 * scale}},
                                          {"to", {offset + 0.75 * scale, 0, 0}}, {"up", {0, 1, 0}}}}}}};
  return {{"settings", {{"width", 8}, {"height", 8}, {"samples", 16}, {"max_bounces", 1}}},
          {"camera", cam},
          {"world", {{"color", {0, 0, 0}}}},
          {"materials", {{{"name", "floor"}, {"type", "diffuse"}, {"color", {1, 1, 1}}}}},
          {"meshes", {{{"name", "floor"}, {"shape", {{"type", "quad"}, {"size", 20 * scale}}}, {"materials", {"floor"}},
                       {"transform", {{"translate", {offset, 0, 0}}}}}}},
          {"lights", {{{"name", "Lamp"}, {"type", "point"}, {"position", {offset, 0, scale}}, {"power", 100}, {"radius", 0},
                       {"emission", {{"strength", strength}}}}}}};
}

}  // namespace

TEST(LightFalloff, PointLampMatchesTheClosedFormInPathAndBdpt) {
  const double d = 1.25, cos_floor = 0.8, intensity = 100.0 / (4 * M_PI);
  struct Case { const char *output; double strength, smooth, factor; };
  const Case cases[] = {{"LINEAR", 2.0, 0.0, 2.0 * d},
                        {"CONSTANT", 2.0, 0.0, 2.0 * d * d},
                        {"QUADRATIC", 2.0, 0.5, 2.0 * d * d / (0.5 + d * d)},
                        {"LINEAR", 2.0, 3.0, 2.0 * d * d * d / (3.0 + d * d)}};
  for (const Case &c : cases) {
    json strength = {{"node", "light_falloff"}, {"output", c.output}, {"strength", c.strength}, {"smooth", c.smooth}};
    const double expected = intensity * c.factor * cos_floor / (d * d) / M_PI;
    for (const char *integrator : {"path", "bdpt"}) {
      Image im = render_json(floor_under_point_lamp(strength).dump(), json({{"integrator", integrator}}).dump());
      ASSERT_TRUE(im.all_finite());
      EXPECT_NEAR(im.channel_mean(1), expected, 1e-3 * expected)
          << integrator << " " << c.output << " smooth " << c.smooth;
    }
  }
  // Millimetres at the origin and kilometres 1,000 km from it: the same closed form with d
  // scaled (Linear d, Constant d^2 over the inverse square).
  for (const auto &[scale, offset] : {std::pair{1e-3, 0.0}, std::pair{1e3, 1e6}})
    for (const char *output : {"LINEAR", "CONSTANT"}) {
      const double ds = d * scale, factor = std::string(output) == "LINEAR" ? ds : ds * ds;
      const double expected = intensity * factor * cos_floor / (ds * ds) / M_PI;
      json strength = {{"node", "light_falloff"}, {"output", output}, {"strength", 1.0}, {"smooth", 0.0}};
      for (const char *integrator : {"path", "bdpt"}) {
        Image im = render_json(floor_under_point_lamp(strength, scale, offset).dump(),
                               json({{"integrator", integrator}}).dump());
        ASSERT_TRUE(im.all_finite());
        EXPECT_NEAR(im.channel_mean(1), expected, 2e-3 * expected)
            << integrator << " " << output << " at scale " << scale << " offset " << offset;
      }
    }
}

TEST(LightFalloff, PathAndBdptAgreeOnEveryKindOfEmitter) {
  expect_small_bdpt_matches_path(load_scene("light_falloff.json"), "light falloff");
}

}  // namespace test_light_falloff
