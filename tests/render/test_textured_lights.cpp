// Textured emission and filtered texture lookups in renders.
//  - A quad whose emission is a two-tone image lights a white floor: the floor's
//    radiance at a point has a closed form (the rectangle's form factor, per half), and
//    PT and BDPT both match it (z-test on the pixel mean at |z| < 4.5 with a 1e-3
//    relative allowance; false-alarm rate about 1e-5 per check).
//  - The same light seen by the camera and lighting the floor (a checker texture): PT
//    and BDPT give the same image (per-block Welch t-tests, 1% false-alarm rate for the
//    file, Sidak-corrected per block).
//  - A high-frequency checker seen far away at a grazing angle at 1 spp shows its mean
//    in every pixel (filtered over the ray's footprint), while a near view keeps the
//    checker's detail; unfiltered (Closest) the far view is noise. Thresholds are wide
//    of the expected values (deterministic renders with fixed seeds).
//  - The same checker seen in a rough metal floor at 1 spp (path tracer): the ray cone
//    widens at the rough bounce, so every sample looks the checker up at a coarse MIP
//    level (its mean, little noise); in a mirror floor the cone stays narrow and the
//    checker's texels show (noise at 1 spp).
#include <gtest/gtest.h>
#include <OpenImageIO/imageio.h>
#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include "render_helpers.h"
#include "statistics.h"

namespace test_textured_lights {

using namespace rdv::test;
using nlohmann::json;

namespace {

// A w x h single-channel image from a texel function (row 0 at the top).
template <class F>
std::string write_image(const std::string &name, int w, int h, OIIO::TypeDesc format, F texel) {
  std::string path = temp_path(name);
  std::vector<float> px(size_t(w) * h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) px[size_t(y) * w + x] = texel(x, y);
  auto out = OIIO::ImageOutput::create(path);
  EXPECT_TRUE(out && out->open(path, OIIO::ImageSpec(w, h, 1, format))) << path;
  EXPECT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, px.data()));
  out->close();
  return path;
}

// Form factor from a point to the rectangle [0, x] x [0, y] parallel to it at height h
// (a corner above the point), signed by the quadrant: rectangles anywhere follow by
// inclusion-exclusion of their corners.
double corner_form_factor(double x, double y, double h) {
  double sx = x < 0 ? -1 : 1, sy = y < 0 ? -1 : 1;
  double a = std::fabs(x) / h, b = std::fabs(y) / h;
  double ra = std::sqrt(1 + a * a), rb = std::sqrt(1 + b * b);
  return sx * sy * (a / ra * std::atan(b / ra) + b / rb * std::atan(a / rb)) / (2 * M_PI);
}
double rect_form_factor(double x0, double x1, double y0, double y1, double h) {
  return corner_form_factor(x1, y1, h) - corner_form_factor(x0, y1, h) - corner_form_factor(x1, y0, h) +
         corner_form_factor(x0, y0, h);
}

// A 2 x 2 m quad at height 1 emitting `emission` (a texture node), over a white floor.
json lit_floor(const json &emission, const json &camera, int size) {
  return {{"settings", {{"width", size}, {"height", size}, {"samples", 64}, {"max_bounces", 4}}},
          {"camera", camera},
          {"world", {{"color", {0, 0, 0}}}},
          {"materials", {{{"name", "floor"}, {"type", "diffuse"}, {"color", {1, 1, 1}}},
                         {{"name", "lamp"}, {"type", "emission"}, {"color", emission}, {"strength", 1}}}},
          {"meshes", {{{"name", "floor"}, {"shape", {{"type", "quad"}, {"size", 20}}}, {"materials", {"floor"}}},
                      {{"name", "lamp"}, {"shape", {{"type", "quad"}, {"size", 2}}}, {"materials", {"lamp"}},
                       {"transform", {{"translate", {0, 0, 1}}}}}}}};
}

}  // namespace

TEST(TexturedEmission, TwoToneQuadMatchesTheClosedFormInPtAndBdpt) {
  // Left half (u < 0.5) radiance 4, right half 1: a 2 x 1 image, Closest.
  std::string img = write_image("two_tone.exr", 2, 1, OIIO::TypeDesc::FLOAT, [](int x, int) { return x ? 1.0f : 4.0f; });
  json tex = {{"node", "image"}, {"file", img}, {"colorspace", "Non-Color"}, {"interpolation", "Closest"}};
  // Looking straight down at the floor point under the middle of the left half,
  // x = -0.5 (a 2 cm wide view: the radiance is flat there to < 1e-4).
  json cam = {{"type", "orthographic"}, {"ortho_scale", 0.02}, {"clip_start", 0.001},
              {"transform", {{"look_at", {{"from", {-0.5, 0, 0.5}}, {"to", {-0.5, 0, 0}}, {"up", {0, 1, 0}}}}}}};
  json scene = lit_floor(tex, cam, 8);
  // Radiance = albedo x sum over the halves of L_k F_k (Lambertian floor, albedo 1).
  double left = rect_form_factor(-0.5, 0.5, -1, 1, 1.0), right = rect_form_factor(0.5, 1.5, -1, 1, 1.0);
  double expected = 4.0 * left + 1.0 * right;
  for (const char *integrator : {"path", "bdpt"}) {
    Image im = render_json(scene.dump(), json({{"integrator", integrator}, {"samples", 256}}).dump());
    ASSERT_TRUE(im.all_finite()) << integrator;
    for (int c = 0; c < 3; ++c) {
      MeanEstimate m = pixel_mean(im, c);
      double z = (m.mean - expected) / std::hypot(m.standard_error, 1e-3 * expected);
      EXPECT_LT(std::fabs(z), 4.5) << integrator << " channel " << c << ": " << m.mean << " expected " << expected;
    }
  }
}

TEST(TexturedEmission, PtAndBdptAgreeOnATexturedLamp) {
  // A coloured checker on the lamp, seen by the camera (emitter hits) and lighting the
  // floor (light sampling, light subpaths).
  json tex = {{"node", "checker"}, {"scale", 3}, {"vector", {{"node", "texture_coordinate"}, {"output", "uv"}}},
              {"color1", {3, 1, 0.2}}, {"color2", {0.2, 0.5, 2}}};
  json cam = {{"type", "perspective"}, {"transform", {{"look_at", {{"from", {0, -4.5, 2.2}}, {"to", {0, 0, 0.5}}}}}}};
  json scene = lit_floor(tex, cam, 32);
  const int kRuns = 6;
  const double alpha_per_block = 1.0 - std::pow(1.0 - 0.01, 1.0 / 16);
  auto runs = [&](const char *integrator, int samples, uint32_t seed) {
    std::vector<std::vector<double>> r;
    for (int k = 0; k < kRuns; ++k) {
      Image im = render_json(scene.dump(), json({{"integrator", integrator}, {"samples", samples},
                                                 {"seed", seed + k}}).dump());
      EXPECT_TRUE(im.all_finite());
      std::vector<double> v(size_t(im.width) * im.height);
      for (size_t i = 0; i < v.size(); ++i) v[i] = double(im.rgba[4 * i]) + im.rgba[4 * i + 1] + im.rgba[4 * i + 2];
      r.push_back(v);
    }
    return r;
  };
  BlockComparison c = compare_blocks(runs("bdpt", 16, 100), runs("path", 32, 200), 32, 32, 8, alpha_per_block);
  EXPECT_EQ(c.failed, 0) << c.detail;
}

namespace {

// A 20 x 20 m plane whose emission is a 512 x 512 checker of single texels (sRGB
// 0 / 255: scene-linear 0 / 1, mean 0.5), seen by a 32 x 32 camera at 1 spp.
Image checker_plane(const json &camera, const char *interpolation) {
  std::string img = write_image("checker512.png", 512, 512, OIIO::TypeDesc::UINT8,
                                [](int x, int y) { return float((x + y) % 2); });
  json tex = {{"node", "image"}, {"file", img}, {"interpolation", interpolation}};
  json j = {{"settings", {{"width", 32}, {"height", 32}, {"samples", 1}, {"max_bounces", 1}}},
            {"camera", camera},
            {"world", {{"color", {0, 0, 0}}}},
            {"materials", {{{"name", "checker"}, {"type", "emission"}, {"color", tex}, {"strength", 1}}}},
            {"meshes", {{{"name", "plane"}, {"shape", {{"type", "quad"}, {"size", 20}}}, {"materials", {"checker"}}}}}};
  return render_json(j.dump());
}

struct PixelStats { double mean, stddev; };
PixelStats pixel_stats(const Image &im) {
  double s = 0, s2 = 0;
  int n = im.width * im.height;
  for (int i = 0; i < n; ++i) {
    double v = im.rgba[4 * size_t(i)];
    s += v;
    s2 += v * v;
  }
  double mean = s / n;
  return {mean, std::sqrt(std::max(s2 / n - mean * mean, 0.0))};
}

}  // namespace

TEST(TextureFiltering, DistantGrazingCheckerShowsItsMeanAtOneSample) {
  // 10 m away, 20 degrees above the plane, a 14 degree view: a pixel covers about
  // 2 x 6 texels.
  json far = {{"type", "perspective"}, {"focal_length", 150},
              {"transform", {{"look_at", {{"from", {0, -9.4, 3.4}}, {"to", {0, 0, 0}}}}}}};
  // The checker's mean as unfiltered lookups see it (texels 0 and 1, their sRGB values
  // interpolated and then converted, as Cycles does): 0.2463 (texture_images' unit test).
  PixelStats filtered = pixel_stats(checker_plane(far, "Linear"));
  EXPECT_NEAR(filtered.mean, 0.2463, 0.01);
  EXPECT_LT(filtered.stddev, 0.03) << "a distant checker should be its average, not noise";
  PixelStats closest = pixel_stats(checker_plane(far, "Closest"));  // never filtered, as in Blender
  EXPECT_GT(closest.stddev, 0.3);
  // 0.3 m above the plane, looking down: a pixel covers a fifth of a texel.
  json near = {{"type", "perspective"}, {"transform", {{"look_at", {{"from", {0.01, 0.02, 0.3}}, {"to", {0.01, 0.02, 0}}, {"up", {0, 1, 0}}}}}}};
  PixelStats detail = pixel_stats(checker_plane(near, "Linear"));
  EXPECT_GT(detail.stddev, 0.1) << "a near checker keeps its detail (bilinear between texels)";
  std::printf("[ filtering ] far: mean %.3f stddev %.4f (Closest: stddev %.3f); near: stddev %.3f\n", filtered.mean,
              filtered.stddev, closest.stddev, detail.stddev);
}

TEST(TextureFiltering, RoughReflectionLooksTheTextureUpAtACoarserLevel) {
  // A 4 m metal floor (white Fresnel) at z = 0 under the checker plane of 20 m (3.9 cm
  // texels, emitting from both faces) at z = 2; the camera at z = 1 looks straight
  // down with a 14 degree view: a pixel's cone is 0.6 texels wide when it reaches the
  // checker (3 m). Roughness 0.3 (GGX alpha 0.09) adds 0.18 per metre of spread: about
  // 10 texels after the 2 m up, MIP level ~3, where the checker is its mean, 0.2463 (the
  // mean of its sRGB values interpolated, then converted: DistantGrazingChecker... above).
  // Each render is compared with the same render of a plain 0.5 emission: the same
  // seeds trace the same paths, so what differs is the looked-up texture (and the few
  // light samples, which look up the finest level).
  std::string img = write_image("checker512.png", 512, 512, OIIO::TypeDesc::UINT8,
                                [](int x, int y) { return float((x + y) % 2); });
  json tex = {{"node", "image"}, {"file", img}};
  std::string integrator;
  auto reflection = [&](float roughness, const json &emission) {
    json j = {{"settings", {{"width", 32}, {"height", 32}, {"samples", 1}, {"max_bounces", 1}, {"integrator", integrator}}},
              {"camera", {{"type", "perspective"}, {"focal_length", 150},
                          {"transform", {{"look_at", {{"from", {0.013, 0.027, 1}}, {"to", {0.013, 0.027, 0}}, {"up", {0, 1, 0}}}}}}}},
              {"world", {{"color", {0, 0, 0}}}},
              {"materials", {{{"name", "checker"}, {"type", "emission"}, {"color", emission}, {"strength", 1}},
                             {{"name", "metal"}, {"type", "glossy"}, {"color", {1, 1, 1}}, {"roughness", roughness}}}},
              {"meshes", {{{"name", "floor"}, {"shape", {{"type", "quad"}, {"size", 4}}}, {"materials", {"metal"}}},
                          {{"name", "plane"}, {"shape", {{"type", "quad"}, {"size", 20}}}, {"materials", {"checker"}},
                           {"transform", {{"translate", {0, 0, 2}}}}}}}};
    return render_json(j.dump());
  };
  // Root-mean-square difference of the red channel between the checker and the grey.
  auto rms_from_grey = [&](float roughness) {
    Image checker = reflection(roughness, tex), grey = reflection(roughness, json::array({0.2463, 0.2463, 0.2463}));
    double s = 0;
    int n = checker.width * checker.height;
    for (int i = 0; i < n; ++i) {
      double d = double(checker.rgba[4 * size_t(i)]) - grey.rgba[4 * size_t(i)];
      s += d * d;
    }
    return std::sqrt(s / n);
  };
  for (const char *name : {"path", "bdpt"}) {  // BDPT: its camera subpaths widen their cones too
    integrator = name;
    double rough = rms_from_grey(0.3f), mirror = rms_from_grey(0.0f);
    std::printf("[ filtering ] %s: checker vs grey, rms difference: in a rough floor %.4f, in a mirror floor %.3f\n",
                name, rough, mirror);
    EXPECT_GT(mirror, 0.1) << name << ": a mirror keeps the checker's texels (the scene resolves them)";
    EXPECT_LT(rough, 0.04) << name << ": through a rough reflection the checker should be looked up at its mean";
  }
}

}  // namespace test_textured_lights
