// Cycles' denoising data (film/denoising_passes.h) on a scene with a closed form: an
// orthographic camera looks straight down at a tinted perfect mirror tilted 45 degrees,
// which sends every camera ray sideways onto a diffuse wall outside the view. Every sample
// of a pixel follows the same path, so for every integrator each pixel's Denoising Albedo is
// the mirror's tint x the wall's colour, its Normal the wall's (camera space), its Depth the
// first segment plus the tint's average x the second; the world seen past the mirror's edge
// adds its colour to the albedo. The image is the same with and without them. 16x16, fixed
// seeds.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include "render_helpers.h"

using namespace rdv::test;
using nlohmann::json;

namespace {

constexpr int kSize = 16;
constexpr double kClip = 0.01;
const double kTint[3] = {0.9, 0.8, 0.7}, kWall[3] = {0.2, 0.5, 0.4};

// The mirror is the plane z = y (through the origin, normal (0, -1, 1) / sqrt 2): a ray
// straight down from (x, y0, 3) meets it at z = y0 and leaves along -y to the wall y = -2.
// world: the world's strength (0 for mlt, which does not sample a world an orthographic
// camera sees).
json mirror_scene(const std::string &integrator, bool denoising, double mirror_size = 4, double world = 0) {
  json settings = {{"width", kSize}, {"height", kSize}, {"samples", 8}, {"max_bounces", 4},
                   {"integrator", integrator}, {"mlt_chains", 16}, {"denoising_passes", denoising}};
  return {{"settings", settings},
          {"camera", {{"type", "orthographic"}, {"ortho_scale", 2.0}, {"clip_start", kClip},
                      {"transform", {{"look_at", {{"from", {0, 0, 3}}, {"to", {0, 0, 0}}, {"up", {0, 1, 0}}}}}}}},
          {"world", {{"color", {0.1, 0.2, 0.3}}, {"strength", world}}},
          {"materials", {{{"name", "mirror"}, {"type", "glossy"}, {"color", {kTint[0], kTint[1], kTint[2]}},
                          {"roughness", 0}, {"distribution", "SHARP"}},
                         {{"name", "wall"}, {"type", "diffuse"}, {"color", {kWall[0], kWall[1], kWall[2]}}}}},
          {"meshes", {{{"name", "mirror"}, {"shape", {{"type", "quad"}, {"size", mirror_size}}},
                       {"materials", {"mirror"}}, {"transform", {{"rotate", {45, 0, 0}}}}},
                      {{"name", "wall"}, {"shape", {{"type", "quad"}, {"size", 8}}}, {"materials", {"wall"}},
                       {"transform", {{"translate", {0, -2, 0}}, {"rotate", {90, 0, 0}}}}}}},
          {"lights", {{{"type", "point"}, {"power", 100}, {"radius", 0}, {"transform", {{"translate", {0, -1, 1}}}}}}}};
}

}  // namespace

TEST(DenoisingPasses, MirrorShowsTheWallsFeaturesEveryIntegrator) {
  const double tint_mean = (kTint[0] + kTint[1] + kTint[2]) / 3;
  for (const char *integrator : {"path", "bdpt", "pssmlt", "mmlt", "mlt"}) {
    Image img = render_json(mirror_scene(integrator, true).dump());
    ASSERT_TRUE(img.all_finite()) << integrator;
    ASSERT_EQ(img.denoising_depth.size(), size_t(kSize * kSize)) << integrator;
    for (int y = 0; y < kSize; ++y)
      for (int x = 0; x < kSize; ++x) {
        const size_t i = size_t(y) * kSize + x;
        for (int c = 0; c < 3; ++c)
          ASSERT_NEAR(img.denoising_albedo[i * 3 + c], kTint[c] * kWall[c], 1e-5)
              << integrator << " albedo channel " << c << " pixel " << x << "," << y;
        // The wall faces +y: the camera's up (camera space x right, y up, z along the view).
        ASSERT_NEAR(img.denoising_normal[i * 3 + 0], 0.0, 1e-4) << integrator << " pixel " << x << "," << y;
        ASSERT_NEAR(img.denoising_normal[i * 3 + 1], 1.0, 1e-4) << integrator << " pixel " << x << "," << y;
        ASSERT_NEAR(img.denoising_normal[i * 3 + 2], 0.0, 1e-4) << integrator << " pixel " << x << "," << y;
        // Row y's centre is at y0 = 1 - (y + 0.5) / 8 (depth is linear in y0: the filter's
        // symmetric offsets average out, up to its spread over 8 samples: 0.2 x 1/8 px).
        const double y0 = 1.0 - (y + 0.5) * 2.0 / kSize;
        const double expected = (3.0 - kClip - y0) + tint_mean * (y0 + 2.0);
        ASSERT_NEAR(img.denoising_depth[i], expected, 0.03) << integrator << " pixel " << x << "," << y;
      }
  }
}

TEST(DenoisingPasses, WorldSeenPastTheMirrorGivesItsColourAndNoNormal) {
  // A mirror 1 x 1: pixels past its edge (|y0| > 0.35) see the world straight down, and
  // those on it whose reflection misses nothing still hit the wall; the outermost rows see
  // the world (albedo = its colour, normal and depth 0).
  Image img = render_json(mirror_scene("path", true, 1.0, 1.0).dump());
  ASSERT_TRUE(img.all_finite());
  const double world[3] = {0.1, 0.2, 0.3};
  for (int x = 0; x < kSize; ++x) {
    const size_t i = size_t(0) * kSize + x;  // top row: y0 = 0.9375, off the mirror
    for (int c = 0; c < 3; ++c) {
      ASSERT_NEAR(img.denoising_albedo[i * 3 + c], world[c], 1e-5) << "pixel " << x;
      ASSERT_EQ(img.denoising_normal[i * 3 + c], 0.0f) << "pixel " << x;
    }
    ASSERT_EQ(img.denoising_depth[i], 0.0f) << "pixel " << x;
  }
}

TEST(DenoisingPasses, ImageUnchangedByThem) {
  // The features only read the path: Combined is bit-identical with and without them.
  for (const char *integrator : {"path", "bdpt", "pssmlt"}) {
    Image on = render_json(mirror_scene(integrator, true).dump());
    Image off = render_json(mirror_scene(integrator, false).dump());
    EXPECT_TRUE(off.denoising_depth.empty());
    ASSERT_EQ(on.rgba, off.rgba) << integrator;
  }
}
