// Cycles' light passes (film/light_passes.h): per pixel, Emission + Environment + the
// sum over kinds of (Direct + Indirect) x Color + Volume Direct + Indirect equals Combined
// to float rounding (path tracing, BDPT, every strategy and light tracing's splats
// included, and the Metropolis integrators pssmlt, mmlt and mlt); Combined itself is
// bit-identical with the passes on and off; path tracing and BDPT agree on every pass's
// mean (8 seeds each, |t| < 5 with 14 degrees of freedom: p = 2e-4 each, about 0.4% for the
// 20 non-trivial means); each Metropolis integrator agrees with BDPT on every pass block by
// block (8 seeds each, Welch's t per 8x8 block, 1% false alarms over the 3 x 12 x 12 block
// tests, Sidak-corrected). A small scene with every kind: diffuse floor, glossy and glass
// balls, an emissive ball, the world, a lamp of radius 0.3 and a wide sun (finite: path
// tracing sees their caustics too), optionally fog (mlt: without the world and the sun,
// which it does not sample).
#include <gtest/gtest.h>
#include <cmath>
#include <nlohmann/json.hpp>
#include "render_helpers.h"
#include "statistics.h"

namespace test_light_passes {

using namespace rdv::test;
using nlohmann::json;

namespace {

json passes_scene(bool fog, const json &settings, bool lights_at_infinity = true) {
  json s = {{"width", 32}, {"height", 24}, {"samples", 32}, {"max_bounces", 8}, {"light_passes", true}};
  s.update(settings);
  json mats = {{{"name", "floor"}, {"type", "diffuse"}, {"color", {0.7, 0.6, 0.5}}},
               {{"name", "gloss"}, {"type", "glossy"}, {"color", {0.9, 0.8, 0.6}}, {"roughness", 0.3}},
               {{"name", "glass"}, {"type", "glass"}, {"ior", 1.5}},
               {{"name", "lamp"}, {"type", "emission"}, {"color", {1.0, 0.9, 0.7}}, {"strength", 4}},
               {{"name", "fog"}, {"type", "volume"}, {"volume", {{"sigma_a", 0.1}, {"sigma_s", {0.9, 0.8, 0.7}}}}}};
  json meshes = {{{"name", "floor"}, {"shape", {{"type", "quad"}, {"size", 8}}}, {"materials", {"floor"}}},
                 {{"name", "gloss"}, {"shape", {{"type", "sphere"}, {"radius", 0.45}, {"segments", 32}}},
                  {"materials", {"gloss"}}, {"transform", {{"translate", {-0.7, 0, 0.45}}}}},
                 {{"name", "glass"}, {"shape", {{"type", "sphere"}, {"radius", 0.45}, {"segments", 32}}},
                  {"materials", {"glass"}}, {"transform", {{"translate", {0.7, 0, 0.45}}}}},
                 {{"name", "lamp"}, {"shape", {{"type", "sphere"}, {"radius", 0.15}, {"segments", 16}}},
                  {"materials", {"lamp"}}, {"transform", {{"translate", {0, 0.9, 1.3}}}}}};
  if (fog)
    meshes.push_back({{"name", "fog"}, {"shape", {{"type", "box"}, {"size", {1.2, 0.8, 0.8}}}},
                      {"materials", {"fog"}}, {"transform", {{"translate", {0, -1.4, 0.6}}}}});
  json lights = {{{"type", "point"}, {"position", {1.5, -1.5, 3}}, {"power", 300}, {"radius", 0.3}}};
  if (lights_at_infinity)
    lights.push_back({{"type", "sun"}, {"strength", 1.5}, {"angle", 0.3}, {"direction", {0.4, 0.3, -1}}});
  return {{"settings", s},
          {"camera", {{"type", "perspective"}, {"focal_length", 35},
                      {"transform", {{"look_at", {{"from", {0, -4, 1.4}}, {"to", {0, 0, 0.5}}}}}}}},
          {"world", {{"color", {0.2, 0.3, 0.5}}, {"strength", lights_at_infinity ? 1 : 0}}},
          {"materials", mats},
          {"meshes", meshes},
          {"lights", lights}};
}

// The Metropolis integrators' settings for these tests (small: a chain count and a
// bootstrap that a 32 x 24 image needs).
json metropolis(const char *integrator, int mutations) {
  return {{"integrator", integrator}, {"samples", mutations}, {"mlt_chains", 64}, {"mlt_bootstrap", 4}};
}
// mlt samples no light at infinity: its scene has neither world nor sun.
bool needs_finite_lights(const std::string &integrator) { return integrator == "mlt"; }

// Emission + Environment + sum (Direct + Indirect) x Color + volume, at pixel (x, y).
void reconstruct(const Image &img, int x, int y, float out[3]) {
  for (int c = 0; c < 3; ++c) {
    float v = img.light_pass(RDV_PASS_EMISSION, x, y)[c] + img.light_pass(RDV_PASS_ENVIRONMENT, x, y)[c];
    for (int kind = 0; kind < 3; ++kind) {
      const rdv_pass direct = rdv_pass(RDV_PASS_DIFFUSE_DIRECT + 3 * kind);
      const float color = img.light_pass(rdv_pass(direct + 2), x, y)[c];
      v += (img.light_pass(direct, x, y)[c] + img.light_pass(rdv_pass(direct + 1), x, y)[c]) * color;
    }
    v += img.light_pass(RDV_PASS_VOLUME_DIRECT, x, y)[c] + img.light_pass(RDV_PASS_VOLUME_INDIRECT, x, y)[c];
    out[c] = v;
  }
}

// Whether Direct / Indirect x Color gives back what the pixel's passes hold: every colour
// channel of a kind non-zero, or that kind's colour 0 within 2 pixels (BDPT's splats reach
// 1.5 pixels from where the camera saw their first vertex; Cycles reads a pass over a
// colour of 0 as 0).
bool reconstructible(const Image &img, int x, int y) {
  for (int kind = 0; kind < 3; ++kind) {
    const rdv_pass color = rdv_pass(RDV_PASS_DIFFUSE_COLOR + 3 * kind);
    const float *c = img.light_pass(color, x, y);
    if (c[0] > 0 && c[1] > 0 && c[2] > 0) continue;
    for (int dy = -2; dy <= 2; ++dy)
      for (int dx = -2; dx <= 2; ++dx) {
        int nx = x + dx, ny = y + dy;
        if (nx < 0 || ny < 0 || nx >= img.width || ny >= img.height) continue;
        const float *n = img.light_pass(color, nx, ny);
        if (n[0] != 0 || n[1] != 0 || n[2] != 0) return false;
      }
  }
  return true;
}

void expect_sum_is_combined(bool fog, const char *integrator, const json &settings = json::object()) {
  json s = {{"integrator", integrator}};
  s.update(settings);
  Image img = render_json(passes_scene(fog, s, !needs_finite_lights(integrator)).dump());
  ASSERT_TRUE(img.warnings.find("light_passes") == std::string::npos) << img.warnings;
  ASSERT_TRUE(img.all_finite());
  ASSERT_EQ(img.light_passes.size(), 13u);
  int checked = 0;
  double worst = 0;
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      for (const auto &pass : img.light_passes)
        for (int c = 0; c < 3; ++c) ASSERT_TRUE(std::isfinite(pass[(size_t(y) * img.width + x) * 3 + c]));
      // Path tracing has no splats: every pixel's passes come from its own samples.
      if (std::string(integrator) != "path" && !reconstructible(img, x, y)) continue;
      ++checked;
      float sum[3];
      reconstruct(img, x, y, sum);
      for (int c = 0; c < 3; ++c) {
        const float combined = img.rgba[(size_t(y) * img.width + x) * 4 + c];
        const double error = std::fabs(sum[c] - combined) / (std::fabs(combined) + 1e-3);
        worst = std::max(worst, error);
        EXPECT_LT(error, 2e-5) << integrator << " pixel " << x << "," << y << " channel " << c << ": passes "
                               << sum[c] << " vs Combined " << combined;
      }
    }
  std::printf("%s%s: %d of %d pixels reconstructible, worst relative error %.3g\n", integrator, fog ? " (fog)" : "",
              checked, img.width * img.height, worst);
  EXPECT_GT(checked, img.width * img.height / 2) << integrator;
}

// Mean over the image of each light pass's channel sum, and of Combined's.
std::vector<double> pass_means(const Image &img) {
  std::vector<double> m;
  for (const auto &pass : img.light_passes) {
    double s = 0;
    for (float v : pass) s += v;
    m.push_back(s / (img.width * img.height));
  }
  return m;
}

}  // namespace

TEST(LightPasses, SumIsCombinedPath) {
  expect_sum_is_combined(false, "path");
  expect_sum_is_combined(true, "path");
}

TEST(LightPasses, SumIsCombinedBdpt) {
  expect_sum_is_combined(false, "bdpt");
  expect_sum_is_combined(true, "bdpt");
}

TEST(LightPasses, SumIsCombinedMetropolis) {
  for (const char *integrator : {"pssmlt", "mmlt", "mlt"}) {
    expect_sum_is_combined(false, integrator, metropolis(integrator, 32));
    expect_sum_is_combined(true, integrator, metropolis(integrator, 32));
  }
}

TEST(LightPasses, CombinedUnchangedByPasses) {
  for (const char *integrator : {"path", "bdpt", "pssmlt", "mmlt", "mlt"}) {
    json s = {{"integrator", integrator}, {"samples", 8}};
    if (std::string(integrator) != "path" && std::string(integrator) != "bdpt") s = metropolis(integrator, 8);
    const bool infinite = !needs_finite_lights(integrator);
    Image on = render_json(passes_scene(true, s, infinite).dump());
    s["light_passes"] = false;
    Image off = render_json(passes_scene(true, s, infinite).dump());
    ASSERT_EQ(on.rgba.size(), off.rgba.size());
    EXPECT_TRUE(off.light_passes.empty());
    size_t differ = 0;
    for (size_t i = 0; i < on.rgba.size(); ++i) differ += on.rgba[i] != off.rgba[i];
    EXPECT_EQ(differ, 0u) << integrator << ": Combined changed with the light passes on";
  }
}

TEST(LightPasses, PathAndBdptAgree) {
  constexpr int kSeeds = 8;
  for (bool fog : {false, true}) {
    std::vector<std::vector<double>> runs[2];
    const char *integrators[2] = {"path", "bdpt"};
    for (int i = 0; i < 2; ++i)
      for (uint32_t seed = 0; seed < kSeeds; ++seed)
        runs[i].push_back(pass_means(
            render_json(passes_scene(fog, {{"integrator", integrators[i]}, {"seed", seed}, {"samples", 64}}).dump())));
    static const char *names[13] = {"Emit",     "Env",      "DiffDir",  "DiffInd",  "DiffCol",   "GlossDir", "GlossInd",
                                    "GlossCol", "TransDir", "TransInd", "TransCol", "VolumeDir", "VolumeInd"};
    for (int p = 0; p < 13; ++p) {
      double mean[2], var[2];
      for (int i = 0; i < 2; ++i) {
        double s = 0, s2 = 0;
        for (const auto &r : runs[i]) { s += r[p]; s2 += r[p] * r[p]; }
        mean[i] = s / kSeeds;
        var[i] = std::max(s2 / kSeeds - mean[i] * mean[i], 0.0) / (kSeeds - 1);  // variance of the mean
      }
      const double z = (mean[0] - mean[1]) / std::sqrt(var[0] + var[1] + 1e-12 + 1e-6 * mean[0] * mean[0]);
      std::printf("%s%s: path %.5f bdpt %.5f z %.2f\n", names[p], fog ? " (fog)" : "", mean[0], mean[1], z);
      EXPECT_LT(std::fabs(z), 5.0) << names[p] << (fog ? " (fog)" : "") << ": path " << mean[0] << " vs bdpt "
                                   << mean[1];
    }
  }
}

// Each Metropolis integrator against BDPT, pass by pass (what each adds to Combined: a
// Direct or Indirect pass times its Color, the Color passes themselves), block by block,
// on the scene without lights at infinity (which every integrator renders) with fog.
TEST(LightPasses, MetropolisAgreesWithBdpt) {
  constexpr int kRuns = 8, kBlock = 8, kWidth = 32, kHeight = 24;
  constexpr int kPasses = 13;  // all but Environment (no world), and Combined
  const int blocks = (kWidth / kBlock) * (kHeight / kBlock);
  const double alpha = 1.0 - std::pow(1.0 - 0.01, 1.0 / (3.0 * kPasses * blocks));
  static const char *names[14] = {"Emit",     "Env",      "DiffDir",  "DiffInd",  "DiffCol",   "GlossDir", "GlossInd",
                                  "GlossCol", "TransDir", "TransInd", "TransCol", "VolumeDir", "VolumeInd", "Combined"};
  // runs[pass][run]: per pixel R + G + B of the pass's contribution.
  auto render_runs = [&](const json &settings, uint32_t seed0) {
    std::vector<std::vector<std::vector<double>>> runs(14);  // the 13 passes, Combined
    for (int k = 0; k < kRuns; ++k) {
      json s = settings;
      s["seed"] = seed0 + uint32_t(k);
      Image img = render_json(passes_scene(true, s, false).dump());
      EXPECT_TRUE(img.all_finite());
      EXPECT_EQ(img.light_passes.size(), 13u);
      if (img.light_passes.size() != 13u) return runs;
      for (int p = 0; p < 13; ++p) {
        std::vector<double> v(size_t(kWidth) * kHeight);
        for (int y = 0; y < kHeight; ++y)
          for (int x = 0; x < kWidth; ++x) {
            const rdv_pass pass = rdv_pass(RDV_PASS_EMISSION + p);
            const int kind = (p - 2) / 3;  // Direct / Indirect of a kind with a colour: times it
            const bool divided = p >= 2 && p < 11 && (p - 2) % 3 != 2;
            const float *value = img.light_pass(pass, x, y);
            const float *color = divided ? img.light_pass(rdv_pass(RDV_PASS_DIFFUSE_COLOR + 3 * kind), x, y) : nullptr;
            double sum = 0;
            for (int c = 0; c < 3; ++c) sum += double(value[c]) * (color ? color[c] : 1.0f);
            v[size_t(y) * kWidth + x] = sum;
          }
        runs[size_t(p)].push_back(std::move(v));
      }
      std::vector<double> combined(size_t(kWidth) * kHeight);
      for (size_t i = 0; i < combined.size(); ++i)
        combined[i] = double(img.rgba[4 * i]) + img.rgba[4 * i + 1] + img.rgba[4 * i + 2];
      runs[13].push_back(std::move(combined));
    }
    return runs;
  };
  const auto bdpt = render_runs({{"integrator", "bdpt"}, {"samples", 256}}, 1);
  for (const char *integrator : {"pssmlt", "mmlt", "mlt"}) {
    const auto mlt = render_runs(metropolis(integrator, 512), 3001);
    for (int p = 0; p < 14; ++p) {
      if (p == 1) continue;  // Environment: no world
      if (mlt[size_t(p)].size() != size_t(kRuns) || bdpt[size_t(p)].size() != size_t(kRuns)) return;
      BlockComparison c = compare_blocks(mlt[size_t(p)], bdpt[size_t(p)], kWidth, kHeight, kBlock, alpha);
      std::printf("[ %-6s vs bdpt ] %-9s mean ratio %.4f, %d of %d blocks differ, worst p %.2g\n", integrator,
                  names[p], c.mean_ratio, c.failed, c.blocks, c.worst_p);
      EXPECT_EQ(c.failed, 0) << integrator << " " << names[p] << ": " << c.detail;
    }
  }
}

}  // namespace test_light_passes
