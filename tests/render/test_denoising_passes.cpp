// Cycles' denoising data (film/denoising_passes.h) on a scene with a closed form: an
// orthographic camera looks straight down at a tinted perfect mirror tilted 45 degrees,
// which sends every camera ray sideways onto a diffuse wall outside the view. Every sample
// of a pixel follows the same path, so for every integrator each pixel's Denoising Albedo is
// the mirror's tint x the wall's colour, its Normal the wall's (camera space), its Depth the
// first segment plus the tint's average x the second; the world seen past the mirror's edge
// adds its colour to the albedo, an emitter seen directly its emission on top of its albedo.
// The image is the same with and without them.
// Fog as Cycles 3.4 writes it (kernel/integrator/shade_volume.h): the same camera looks down
// through a fog slab at a floor; every sample adds albedo x (1 - transmittance) of the slab
// whether it scatters there or not, and the floor's albedo if it reaches it. A black floor
// makes that exact per sample (homogeneous, chromatic); a grey floor gives the closed-form
// mean albedo x (1 - T) + T x floor; a grid slab's transmittance is estimated per sample.
// 16x16, fixed seeds.
#include <gtest/gtest.h>
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>
#include "render_helpers.h"

namespace test_denoising_passes {

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

// The fog slab: z from 1 to 2 (thickness 1) between the camera at z = 3 and a diffuse
// floor at z = 0, both wider than the view.
json fog_scene(const std::string &integrator, bool denoising, const json &fog, double floor, int samples = 8) {
  json scene = mirror_scene(integrator, denoising);
  scene["settings"]["samples"] = samples;
  scene["materials"] = {{{"name", "floor"}, {"type", "diffuse"}, {"color", {floor, floor, floor}}},
                        {{"name", "fog"}, {"type", "volume"}, {"volume", fog}}};
  scene["meshes"] = {{{"name", "floor"}, {"shape", {{"type", "quad"}, {"size", 8}}}, {"materials", {"floor"}}},
                     {{"name", "fog"}, {"shape", {{"type", "box"}, {"size", {6.0, 6.0, 1.0}}}}, {"materials", {"fog"}},
                      {"transform", {{"translate", {0, 0, 1.5}}}}}};
  scene["lights"][0]["transform"] = {{"translate", {2, 0, 2.5}}};
  return scene;
}
const double kSigmaS[3] = {0.3, 0.6, 0.9}, kSigmaA[3] = {0.5, 0.2, 0.1};  // sigma_t 0.8, 0.8, 1.0
json chromatic_fog() {
  return {{"sigma_s", {kSigmaS[0], kSigmaS[1], kSigmaS[2]}}, {"sigma_a", {kSigmaA[0], kSigmaA[1], kSigmaA[2]}}};
}
// Densities along z through the grid slab: optical depth = sigma_t x 0.125 x their sum.
const std::vector<float> kGridProfile = {0.2f, 1.5f, 0.1f, 3.0f, 0.5f, 0.0f, 2.0f, 1.0f};
json grid_fog(const std::string &method) {
  return {{"sigma_s", 0.6}, {"sigma_a", 0.2}, {"method", method},
          {"grid", {{"resolution", {1, 1, 8}}, {"values", kGridProfile}, {"bounds", {{-3, -3, 1}, {3, 3, 2}}}}}};
}

// The mean of one channel of the albedo over the pixels, and its standard error.
std::pair<double, double> albedo_mean(const Image &img, int c) {
  const int n = img.width * img.height;
  double s = 0, s2 = 0;
  for (int i = 0; i < n; ++i) {
    const double v = img.denoising_albedo[size_t(i) * 3 + c];
    s += v;
    s2 += v * v;
  }
  const double mean = s / n;
  return {mean, std::sqrt(std::max(s2 / n - mean * mean, 0.0) / (n - 1))};
}

}  // namespace

TEST(DenoisingPasses, FogAddsAlbedoTimesOneMinusTransmittanceEveryIntegrator) {
  // A black floor adds nothing: every sample's albedo is the slab's, scattered or not.
  for (const char *integrator : {"path", "bdpt", "pssmlt", "mmlt", "mlt"}) {
    Image img = render_json(fog_scene(integrator, true, chromatic_fog(), 0.0).dump());
    ASSERT_TRUE(img.all_finite()) << integrator;
    ASSERT_EQ(img.denoising_albedo.size(), size_t(kSize * kSize * 3)) << integrator;
    for (int i = 0; i < kSize * kSize; ++i)
      for (int c = 0; c < 3; ++c) {
        const double sigma_t = kSigmaS[c] + kSigmaA[c];
        const double expected = kSigmaS[c] / sigma_t * (1 - std::exp(-sigma_t));
        ASSERT_NEAR(img.denoising_albedo[size_t(i) * 3 + c], expected, 1e-5)
            << integrator << " albedo channel " << c << " pixel " << i;
      }
  }
}

TEST(DenoisingPasses, FogInFrontOfAFloorGivesTheClosedFormSum) {
  // Grey fog (albedo 0.75, T = exp(-0.8)) over a floor of albedo 0.5: the samples that pass
  // (a fraction T) add the floor's; Normal is (0, 0, -1) either way (the floor faces the
  // camera). 64 samples a pixel: the mean's standard error is about 0.002.
  const double a = 0.75, T = std::exp(-0.8), floor = 0.5;
  const double expected = a * (1 - T) + T * floor;
  for (const char *integrator : {"path", "bdpt"}) {
    Image img = render_json(fog_scene(integrator, true, {{"sigma_s", 0.6}, {"sigma_a", 0.2}}, floor, 64).dump());
    ASSERT_TRUE(img.all_finite()) << integrator;
    for (int c = 0; c < 3; ++c) {
      auto [mean, se] = albedo_mean(img, c);
      if (c == 0) std::printf("%s: albedo mean %.4f, closed form %.4f (se %.4f)\n", integrator, mean, expected, se);
      EXPECT_LT(std::fabs(mean - expected) / se, 4.5)
          << integrator << " channel " << c << ": mean " << mean << " expected " << expected << " (se " << se << ")";
    }
    for (int i = 0; i < kSize * kSize; ++i) {
      ASSERT_NEAR(img.denoising_normal[size_t(i) * 3 + 0], 0.0, 1e-5) << integrator << " pixel " << i;
      ASSERT_NEAR(img.denoising_normal[size_t(i) * 3 + 1], 0.0, 1e-5) << integrator << " pixel " << i;
      ASSERT_NEAR(img.denoising_normal[size_t(i) * 3 + 2], -1.0, 1e-5) << integrator << " pixel " << i;
    }
  }
}

TEST(DenoisingPasses, GridFogAddsAlbedoTimesOneMinusItsTransmittance) {
  // The grid's transmittance per sample is an unbiased estimate: the mean albedo over the
  // image is 0.75 (1 - exp(-0.8 x 0.125 x sum of the densities)), black floor.
  double depth = 0;
  for (float v : kGridProfile) depth += v;
  const double expected = 0.75 * (1 - std::exp(-0.8 * 0.125 * depth));
  for (const char *method : {"tracking", "ray_marching"}) {
    for (const char *integrator : {"path", "bdpt"}) {
      Image img = render_json(fog_scene(integrator, true, grid_fog(method), 0.0, 16).dump());
      ASSERT_TRUE(img.all_finite()) << method << " " << integrator;
      auto [mean, se] = albedo_mean(img, 1);
      std::printf("%s %s: albedo mean %.4f, expected %.4f (se %.4f)\n", method, integrator, mean, expected, se);
      // Ray marching is approximate: 2% of the value on top of the noise.
      const double tolerance = std::hypot(se, std::string(method) == "ray_marching" ? 0.02 * expected : 0.0);
      EXPECT_LT(std::fabs(mean - expected) / tolerance, 4.5)
          << method << " " << integrator << ": mean " << mean << " expected " << expected << " (se " << se << ")";
    }
  }
}

TEST(DenoisingPasses, EmitterSeenDirectlyAddsItsEmissionToItsAlbedo) {
  // A diffuse floor that also emits, seen straight down: Cycles writes the emission the
  // camera ray finds and then the surface's albedo, both to Denoising Albedo.
  const double color[3] = {0.2, 0.5, 0.4}, emission[3] = {0.3, 0.2, 0.1};
  for (const char *integrator : {"path", "bdpt", "pssmlt", "mmlt", "mlt"}) {
    json scene = fog_scene(integrator, true, chromatic_fog(), 0.0);
    scene["meshes"].erase(1);  // no fog
    scene["materials"][0]["color"] = {color[0], color[1], color[2]};
    scene["materials"][0]["emission"] = {emission[0], emission[1], emission[2]};
    Image img = render_json(scene.dump());
    ASSERT_TRUE(img.all_finite()) << integrator;
    for (int i = 0; i < kSize * kSize; ++i)
      for (int c = 0; c < 3; ++c)
        ASSERT_NEAR(img.denoising_albedo[size_t(i) * 3 + c], color[c] + emission[c], 1e-5)
            << integrator << " albedo channel " << c << " pixel " << i;
  }
}

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
    // Fog: the features estimate a grid's transmittance with numbers of their own.
    for (const json &fog : {chromatic_fog(), grid_fog("tracking")}) {
      Image fog_on = render_json(fog_scene(integrator, true, fog, 0.5).dump());
      Image fog_off = render_json(fog_scene(integrator, false, fog, 0.5).dump());
      ASSERT_EQ(fog_on.rgba, fog_off.rgba) << integrator << " fog " << fog.dump();
    }
  }
}

}  // namespace test_denoising_passes
