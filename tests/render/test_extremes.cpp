// Numerical stability at the extremes: millimetre- and kilometre-scale scenes (no
// self-shadowing "acne" from the ray offset), mirror-smooth and fully rough
// surfaces, tiny bright lamps. z-tests at |z| < 4.5 (false alarm < 1e-5 per check).
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include "render_helpers.h"

using namespace rdv::test;
using nlohmann::json;

namespace {

// A white floor of size s centred at c, a sun at 60 degrees from the normal, an
// orthographic camera looking straight down: radiance = E cos(60) / pi everywhere.
json sunlit_floor(double s, const std::vector<double> &c) {
  double h = 3 * s;
  return {{"settings", {{"width", 12}, {"height", 12}, {"samples", 64}, {"max_bounces", 4}}},
          {"camera", {{"type", "orthographic"}, {"ortho_scale", s * 0.5}, {"clip_start", s * 0.01}, {"clip_end", h * 2},
                      {"transform", {{"look_at", {{"from", {c[0], c[1], c[2] + h}}, {"to", c}, {"up", {0, 1, 0}}}}}}}},
          {"world", {{"color", {0, 0, 0}}}},
          {"materials", {{{"name", "white"}, {"type", "diffuse"}, {"color", {1, 1, 1}}}}},
          {"meshes", {{{"name", "floor"}, {"shape", {{"type", "quad"}, {"size", s}}}, {"materials", {"white"}},
                       {"transform", {{"translate", c}, {"rotate", {0.0, 0.0, 13.0}}}}}}},
          {"lights", {{{"type", "sun"}, {"direction", {std::sin(M_PI / 3), 0, -std::cos(M_PI / 3)}}, {"angle", 0}, {"strength", 3}}}}};
}

void expect_uniform(const Image &img, double expected, const std::string &what) {
  ASSERT_TRUE(img.all_finite()) << what;
  EXPECT_EQ(img.progress.samples_dropped, 0u) << what;
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x)
      ASSERT_NEAR(img.rgba[(size_t(y) * img.width + x) * 4], expected, 1e-3 * expected)
          << what << " pixel " << x << "," << y << " (self-shadowing from the ray offset?)";
}

}  // namespace

TEST(Extremes, NoShadowAcneFromMillimetreToKilometre) {
  const double expected = 3 * 0.5 / M_PI;
  expect_uniform(render_json(sunlit_floor(1e-4, {0, 0, 0}).dump()), expected, "0.1 mm floor at the origin");
  expect_uniform(render_json(sunlit_floor(1e-3, {2.5e-3, -1e-3, 7e-4}).dump()), expected, "1 mm floor");
  expect_uniform(render_json(sunlit_floor(1.0, {0, 0, 0}).dump()), expected, "1 m floor");
  expect_uniform(render_json(sunlit_floor(1e3, {1e4, -2e4, 3e3}).dump()), expected, "1 km floor far out");
  expect_uniform(render_json(sunlit_floor(1e5, {1e5, 1e5, 0}).dump()), expected, "100 km floor at 1e5");
}

// Glossy surfaces from mirror (delta) to fully rough under a uniform world stay
// finite and never reflect more than arrives (radiance <= the world's).
TEST(Extremes, RoughnessFromMirrorToRough) {
  for (double r : {0.0, 1e-4, 0.01, 0.05, 0.5, 1.0}) {
    json j = {{"settings", {{"width", 16}, {"height", 16}, {"samples", 16}}},
              {"camera", {{"transform", {{"look_at", {{"from", {0, -4, 1}}, {"to", {0, 0, 0}}}}}}}},
              {"world", {{"color", {1, 1, 1}}}},
              {"materials", {{{"name", "metal"}, {"type", "glossy"}, {"color", {1, 1, 1}}, {"roughness", r}}}},
              {"meshes", {{{"name", "ball"}, {"shape", {{"type", "sphere"}, {"radius", 1}}}, {"materials", {"metal"}}}}}};
    Image img = render_json(j.dump());
    ASSERT_TRUE(img.all_finite()) << "roughness " << r;
    EXPECT_EQ(img.progress.samples_dropped, 0u) << "roughness " << r;
    MeanEstimate m = pixel_mean(img, 0);
    EXPECT_LT(m.mean, 1.0 + 4.5 * m.standard_error + 1e-4) << "roughness " << r;
  }
}

// A tiny, very bright point lamp almost touching a wall: finite everywhere.
TEST(Extremes, TinyBrightLampTouchingAWall) {
  json j = {{"settings", {{"width", 24}, {"height", 24}, {"samples", 16}}},
            {"camera", {{"transform", {{"look_at", {{"from", {0, -3, 0.5}}, {"to", {0, 0, 0}}}}}}}},
            {"world", {{"color", {0, 0, 0}}}},
            {"materials", {{{"name", "grey"}, {"type", "diffuse"}}, {{"name", "mirror"}, {"type", "glossy"}, {"roughness", 0}}}},
            {"meshes", {{{"name", "wall"}, {"shape", {{"type", "quad"}, {"size", 4}}}, {"materials", {"grey"}}},
                        {{"name", "ball"}, {"shape", {{"type", "sphere"}, {"radius", 0.3}}}, {"materials", {"mirror"}},
                         {"transform", {{"translate", {0.6, 0, 0.3}}}}}}},
            {"lights", {{{"type", "point"}, {"position", {0, 0, 1e-5}}, {"radius", 1e-6}, {"power", 1e6}},
                        {{"type", "area"}, {"position", {-0.5, 0, 1e-4}}, {"direction", {0, 0, -1}}, {"size", 1e-3}, {"power", 1e3}}}}};
  Image img = render_json(j.dump());
  EXPECT_TRUE(img.all_finite());
  EXPECT_EQ(img.progress.samples_dropped, 0u);
}
