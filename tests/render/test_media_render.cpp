// Participating media rendered end to end, against closed forms. z-tests on the mean
// over pixels at |z| < 4.5 (false alarm < 1e-5 per check); fixed seeds.
#include <gtest/gtest.h>
#include <array>
#include <nlohmann/json.hpp>
#include "render_helpers.h"

using namespace rdv::test;
using nlohmann::json;

namespace {

void expect_channels(const Image &img, std::array<double, 3> expected, const std::string &what) {
  ASSERT_TRUE(img.all_finite()) << what;
  EXPECT_EQ(img.progress.samples_dropped, 0u) << what;
  for (int c = 0; c < 3; ++c) {
    MeanEstimate m = pixel_mean(img, c);
    double z = (m.mean - expected[c]) / std::hypot(m.standard_error, 2e-5 * expected[c] + 1e-7);
    EXPECT_LT(std::fabs(z), 4.5) << what << " channel " << c << ": mean " << m.mean << " expected " << expected[c]
                                 << " (se " << m.standard_error << ")";
  }
}

}  // namespace

// Beer-Lambert: an orthographic camera looks through a purely absorbing, chromatic
// slab (an index-matched box) at a uniform world: L = L_world exp(-sigma_a d).
TEST(MediaRender, BeerLambertSlab) {
  const double d = 0.8;
  json j = {{"settings", {{"width", 8}, {"height", 8}, {"samples", 64}}},
            {"camera", {{"type", "orthographic"}, {"ortho_scale", 0.5}, {"transform", {{"look_at", {{"from", {0, -5, 0}}, {"to", {0, 0, 0}}}}}}}},
            {"world", {{"color", {2.0, 2.0, 2.0}}}},
            {"materials", {{{"name", "smoke"}, {"type", "volume"},
                            {"volume", {{"sigma_a", {0.5, 1.0, 2.5}}, {"sigma_s", {0, 0, 0}}}}}}},
            {"meshes", {{{"name", "slab"}, {"shape", {{"type", "box"}, {"size", {3.0, d, 3.0}}}}, {"materials", {"smoke"}}}}}};
  expect_channels(render_json(j.dump()), {2 * std::exp(-0.5 * d), 2 * std::exp(-1.0 * d), 2 * std::exp(-2.5 * d)},
                  "absorbing slab");
}

// Kirchhoff's furnace: inside a black enclosure emitting Le, a medium that absorbs,
// scatters (anisotropically) and emits sigma_a Le is in equilibrium: radiance is Le in
// every direction. The camera sits inside the medium; the medium is chromatic.
TEST(MediaRender, VolumetricFurnaceInsideEnclosure) {
  const double Le = 0.6;
  json sa = {0.3, 0.9, 2.0}, ss = {1.5, 0.4, 0.2};
  json j = {{"settings", {{"width", 12}, {"height", 12}, {"samples", 128}, {"max_bounces", 1000}}},
            {"camera", {{"focal_length", 18}, {"transform", {{"look_at", {{"from", {0.1, -0.2, 0.05}}, {"to", {1, 0.3, 0.2}}}}}}}},
            {"world", {{"color", {0, 0, 0}}}},
            {"materials", {{{"name", "shell"}, {"type", "diffuse"}, {"color", {0, 0, 0}}, {"emission", {Le, Le, Le}},
                            {"volume", {{"sigma_a", sa}, {"sigma_s", ss}, {"anisotropy", 0.6},
                                        {"emission", {0.3 * Le, 0.9 * Le, 2.0 * Le}}}}}}},
            {"meshes", {{{"name", "sphere"}, {"shape", {{"type", "sphere"}, {"radius", 1}, {"segments", 24}, {"smooth", false}}},
                         {"materials", {"shell"}}}}}};
  expect_channels(render_json(j.dump()), {Le, Le, Le}, "volumetric furnace");
}

// A conservative (albedo 1) world fog around a white emitter-filled... the classic:
// a uniform world seen through infinite non-absorbing fog stays the world's radiance.
TEST(MediaRender, AlbedoOneFogKeepsUniformWorld) {
  json j = {{"settings", {{"width", 8}, {"height", 8}, {"samples", 64}, {"max_bounces", 1000}}},
            {"camera", {{"transform", {{"look_at", {{"from", {0, -4, 0}}, {"to", {0, 0, 0}}}}}}}},
            {"world", {{"color", {0.7, 0.7, 0.7}}}},
            {"materials", {{{"name", "fog"}, {"type", "volume"}, {"volume", {{"sigma_a", 0}, {"sigma_s", {0.9, 1.2, 0.5}}, {"anisotropy", -0.3}}}}}},
            {"meshes", {{{"name", "cloud"}, {"shape", {{"type", "sphere"}, {"radius", 1.5}, {"smooth", false}}}, {"materials", {"fog"}}}}}};
  expect_channels(render_json(j.dump()), {0.7, 0.7, 0.7}, "albedo-1 fog ball under a uniform world");
}

// Extremes stay finite: densities from 1e-6 to 1e5, albedo 0 and 1, g = +-0.99, a spot
// in world fog.
TEST(MediaRender, ExtremesStayFinite) {
  for (double density : {1e-6, 1.0, 1e5})
    for (double g : {-0.99, 0.99})
      for (double albedo : {0.0, 1.0}) {
        json j = {{"settings", {{"width", 8}, {"height", 8}, {"samples", 4}, {"max_bounces", 64}}},
                  {"camera", {{"transform", {{"look_at", {{"from", {0, -4, 1}}, {"to", {0, 0, 0.5}}}}}}}},
                  {"world", {{"color", {0.1, 0.1, 0.1}}, {"volume", {{"density", density * 1e-3}, {"color", albedo}, {"anisotropy", g}}}}},
                  {"materials", {{{"name", "grey"}, {"type", "diffuse"}},
                                 {{"name", "smoke"}, {"type", "volume"}, {"volume", {{"density", density}, {"color", albedo}, {"anisotropy", g}}}}}},
                  {"meshes", {{{"name", "floor"}, {"shape", {{"type", "quad"}, {"size", 6}}}, {"materials", {"grey"}}},
                              {{"name", "cloud"}, {"shape", {{"type", "box"}, {"size", {1, 1, 1}}}}, {"materials", {"smoke"}},
                               {"transform", {{"translate", {0, 0, 0.6}}}}}}},
                  {"lights", {{{"type", "spot"}, {"position", {0, 0, 3}}, {"direction", {0, 0, -1}}, {"power", 500}}}}};
        Image img = render_json(j.dump());
        EXPECT_TRUE(img.all_finite()) << "density " << density << " g " << g << " albedo " << albedo;
        EXPECT_EQ(img.progress.samples_dropped, 0u) << "density " << density << " g " << g << " albedo " << albedo;
      }
}
