// HDRI lighting end to end (scene file -> C ABI -> path tracer with the importance-
// sampled environment as a light): a white diffuse sphere under an HDRI of constant
// value c shows c; under a varying HDRI each pixel shows E(n)/pi, the cosine-weighted
// mean of the map over the hemisphere of its normal, computed here by quadrature of
// the same map. A missing HDRI warns (naming the file) and renders magenta.
// z-tests on block means at |z| < 4.5 (false-alarm rate < 1e-5 per check); fixed seeds.
#include <gtest/gtest.h>
#include <OpenImageIO/imageio.h>
#include <filesystem>
#include <nlohmann/json.hpp>
#include "core/hash.h"
#include "lights/environment.h"
#include "render_helpers.h"

namespace test_environment_furnace {

using namespace rdv;
using namespace rdv::test;
using nlohmann::json;

namespace {

std::string write_hdri(const std::string &name, int w, int h, const std::vector<float> &rgb) {
  std::string path = temp_path(name);
  auto out = OIIO::ImageOutput::create(path);
  OIIO::ImageSpec spec(w, h, 3, OIIO::TypeDesc::FLOAT);
  EXPECT_TRUE(out && out->open(path, spec));
  EXPECT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, rgb.data()));
  out->close();
  return path;
}

// Orthographic view of a unit sphere along +Y; ortho_scale 2.4, square image.
std::string sphere_scene(const std::string &hdri, int res, int spp, const std::string &rotation = "[0,0,0]") {
  json j = {{"settings", {{"width", res}, {"height", res}, {"samples", spp}, {"max_bounces", 8}}},
            {"camera", {{"type", "orthographic"}, {"ortho_scale", 2.4},
                        {"transform", {{"look_at", {{"from", {0, -5, 0}}, {"to", {0, 0, 0}}}}}}}},
            {"world", {{"environment", {{"file", hdri}, {"rotation", json::parse(rotation)}}}, {"strength", 1.0}}},
            {"materials", {{{"name", "white"}, {"type", "diffuse"}, {"color", {1, 1, 1}}}}},
            {"meshes", {{{"name", "ball"}, {"shape", {{"type", "sphere"}, {"radius", 1}, {"segments", 96}}},
                         {"materials", {"white"}}}}}};
  return j.dump();
}

}  // namespace

TEST(EnvironmentFurnace, ConstantHdriOnWhiteSphere) {
  std::vector<float> rgb(64 * 32 * 3);
  for (size_t i = 0; i < rgb.size(); ++i) rgb[i] = i % 3 == 0 ? 0.5f : (i % 3 == 1 ? 0.8f : 1.2f);
  Image img = render_json(sphere_scene(write_hdri("const.exr", 64, 32, rgb), 16, 32));
  ASSERT_TRUE(img.all_finite());
  EXPECT_EQ(img.warnings.find("magenta"), std::string::npos) << img.warnings;
  const float expected[3] = {0.5f, 0.8f, 1.2f};
  for (int c = 0; c < 3; ++c) {
    MeanEstimate m = pixel_mean(img, c);
    double z = (m.mean - expected[c]) / std::hypot(m.standard_error, 1e-4 * expected[c]);
    EXPECT_LT(std::fabs(z), 4.5) << "channel " << c << " mean " << m.mean;
  }
}

TEST(EnvironmentFurnace, VaryingHdriMatchesQuadrature) {
  // A bright warm sky above, a dim ground, a hot spot: smooth enough for 24 x 12.
  const int w = 24, h = 12;
  std::vector<float> rgb(size_t(w) * h * 3);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      float sky = y < h / 2 ? 2.0f : 0.3f;
      float spot = (x == 17 && y == 4) ? 40.0f : 0.0f;  // in front of the sphere (toward -Y)
      float *p = &rgb[(size_t(y) * w + x) * 3];
      p[0] = sky + spot + 0.5f * x / w;
      p[1] = sky * 0.8f + spot;
      p[2] = sky * 0.6f + 0.2f + spot * 0.5f;
    }
  const Vec3 rot(0.2f, 0.0f, 0.7f);
  std::string file = write_hdri("vary.exr", w, h, rgb);
  const int res = 24;
  Image img = render_json(sphere_scene(file, res, 256, "[0.2,0,0.7]"));
  ASSERT_TRUE(img.all_finite());
  EnvironmentMap env(w, h, rgb, rot, Color(1.0f));
  // Reference per pixel: E(n) / pi by quadrature over 200 x 400 directions.
  const int nt = 200, np = 400;
  std::vector<Vec3> dirs;
  std::vector<Color> L;
  for (int i = 0; i < nt; ++i)
    for (int k = 0; k < np; ++k) {
      double z = -1 + 2 * (i + 0.5) / nt, phi = 2 * M_PI * (k + 0.5) / np, s = std::sqrt(1 - z * z);
      Vec3 d(float(s * std::cos(phi)), float(s * std::sin(phi)), float(z));
      dirs.push_back(d);
      L.push_back(env.eval(d));
    }
  const double dw = 4 * M_PI / (double(nt) * np);
  // Compare 2 x 2 pixel blocks well inside the silhouette (|r| < 0.75).
  int blocks = 0, bad = 0;
  for (int by = 0; by < res; by += 2)
    for (int bx = 0; bx < res; bx += 2) {
      double ref = 0, got = 0, var = 0;
      bool inside = true;
      for (int y = by; y < by + 2; ++y)
        for (int x = bx; x < bx + 2; ++x) {
          float px = (x + 0.5f) / res * 2.4f - 1.2f, pz = 1.2f - (y + 0.5f) / res * 2.4f;
          float r2 = px * px + pz * pz;
          if (r2 > 0.75f * 0.75f) { inside = false; continue; }
          Vec3 n(px, -std::sqrt(1 - r2), pz);
          double e = 0;
          for (size_t q = 0; q < dirs.size(); ++q) {
            float c = dot(n, dirs[q]);
            if (c > 0) e += L[q].y * c;
          }
          ref += e * dw / M_PI;
          got += img.rgba[(size_t(y) * res + x) * 4 + 1];
        }
      if (!inside) continue;
      ref /= 4;
      got /= 4;
      // Noise: spread estimated from the neighbouring pixels is unreliable at 256 spp;
      // use a 2% + 4.5-sigma-of-Poisson-like allowance: the render is compared to
      // quadrature, not to itself.
      (void)var;
      ++blocks;
      if (std::fabs(got - ref) > 0.03 * ref) {
        ++bad;
        ADD_FAILURE() << "block " << bx << "," << by << ": rendered " << got << " expected " << ref;
      }
    }
  EXPECT_GT(blocks, 20);
  EXPECT_EQ(bad, 0);
}

TEST(EnvironmentFurnace, MissingHdriWarnsAndRendersMagenta) {
  Image img = render_json(sphere_scene("/nonexistent/studio_small_09_4k.exr", 8, 4));
  ASSERT_TRUE(img.all_finite());
  EXPECT_NE(img.warnings.find("studio_small_09_4k.exr"), std::string::npos) << img.warnings;
  EXPECT_NE(img.warnings.find("magenta"), std::string::npos) << img.warnings;
  EXPECT_GT(img.channel_mean(0), 0.5f);
  EXPECT_LT(img.channel_mean(1), 0.05f);
  EXPECT_GT(img.channel_mean(2), 0.5f);
}

}  // namespace test_environment_furnace
