// Adaptive sampling (path, bdpt; Cycles' Noise Threshold): pixels whose estimated
// relative error is below the threshold stop receiving samples. The image stays
// unbiased: 8 renders with independent seeds against 8 uniform ones, every 8 x 8 block
// compared with Welch's t-test (1% false alarms for the file, Sidak-corrected per block),
// and the mean brightness within 3.3 standard errors (1e-3). Fixed seeds: reproducible.
#include <gtest/gtest.h>
#include <cmath>
#include <cstring>
#include <nlohmann/json.hpp>
#include "render_helpers.h"
#include "statistics.h"

namespace test_adaptive_sampling {

using namespace rdv::test;
using nlohmann::json;

namespace {

constexpr int kBlockTestsInFile = 2 * 16;  // 2 integrators x 16 blocks of a 32 x 32 image
const double kAlphaPerBlock = 1.0 - std::pow(1.0 - 0.01, 1.0 / kBlockTestsInFile);

json adaptive(const char *integrator) {
  return {{"width", 32}, {"height", 32}, {"integrator", integrator}, {"max_bounces", 8}, {"samples", 128},
          {"adaptive_sampling", true}, {"adaptive_threshold", 0.05}, {"adaptive_min_samples", 8}};
}

double mean_of(const std::vector<double> &v) {
  double s = 0;
  for (double x : v) s += x;
  return s / double(v.size());
}

}  // namespace

TEST(AdaptiveSampling, UnbiasedAgainstUniformSampling) {
  const std::string scene = load_scene("cornell_box.json").dump();
  for (const char *integrator : {"path", "bdpt"}) {
    json s = adaptive(integrator);
    std::vector<std::vector<double>> a = seeded_renders(scene, s.dump(), 8, 1);
    s["adaptive_sampling"] = false;
    std::vector<std::vector<double>> u = seeded_renders(scene, s.dump(), 8, 101);
    BlockComparison c = compare_blocks(a, u, 32, 32, 8, kAlphaPerBlock);
    EXPECT_EQ(c.failed, 0) << integrator << ": " << c.detail;
    std::vector<double> ma, mu;
    for (auto &img : a) ma.push_back(mean_of(img));
    for (auto &img : u) mu.push_back(mean_of(img));
    auto stats = [](const std::vector<double> &x, double &m, double &e) {
      m = mean_of(x);
      double s2 = 0;
      for (double v : x) s2 += (v - m) * (v - m);
      e = std::sqrt(s2 / double(x.size() - 1) / double(x.size()));
    };
    double m1, e1, m2, e2;
    stats(ma, m1, e1);
    stats(mu, m2, e2);
    const double z = (m1 - m2) / std::sqrt(e1 * e1 + e2 * e2);
    std::printf("[ adaptive ] %s: mean %.5f vs uniform %.5f (z %.2f); %s\n", integrator, m1, m2, z,
                c.detail.substr(0, 100).c_str());
    EXPECT_LT(std::fabs(z), 3.3) << integrator;
  }
}

// Converged pixels get fewer samples: the render stops before its sample count, or
// some pixels do; the same image on 1 and 2 threads (checks at fixed sample counts).
TEST(AdaptiveSampling, DeterministicAndStopsPixels) {
  const std::string scene = load_scene("cornell_box.json").dump();
  for (const char *integrator : {"path", "bdpt"}) {
    json s = adaptive(integrator);
    s["threads"] = 1;
    Image one = render_json(scene, s.dump());
    s["threads"] = 2;
    Image two = render_json(scene, s.dump());
    EXPECT_EQ(one.rgba, two.rgba) << integrator;
    EXPECT_EQ(one.progress.samples_done, two.progress.samples_done) << integrator;
    EXPECT_GE(one.progress.noise_estimate, 0.0) << integrator;
    // Fewer samples than uniform sampling: the rays traced tell.
    s["adaptive_sampling"] = false;
    Image uniform = render_json(scene, s.dump());
    std::printf("[ adaptive ] %s: rays %llu vs uniform %llu\n", integrator,
                (unsigned long long)one.progress.rays_traced, (unsigned long long)uniform.progress.rays_traced);
    EXPECT_LT(one.progress.rays_traced, uniform.progress.rays_traced) << integrator;
  }
}

// Settings that cannot work are refused with a message naming them.
TEST(AdaptiveSampling, BadSettingsAreRefused) {
  SceneHandle scene;
  const std::pair<const char *, const char *> cases[] = {
      {R"({"adaptive_sampling": true, "adaptive_threshold": 0})", "adaptive_threshold"},
      {R"({"adaptive_sampling": true, "adaptive_threshold": -1})", "adaptive_threshold"},
      {R"({"adaptive_sampling": true, "adaptive_min_samples": -4})", "adaptive_min_samples"},
      {R"({"adaptive_sampling": true, "integrator": "pssmlt"})", "adaptive_sampling"},
      {R"({"adaptive_sampling": true, "sample_offset": 64})", "sample_offset"}};
  for (const auto &[settings, name] : cases) {
    rdv_session *session = nullptr;
    EXPECT_NE(rdv_session_create(scene.s, settings, &session), RDV_OK) << settings;
    EXPECT_NE(std::string(rdv_last_error()).find(name), std::string::npos) << rdv_last_error();
  }
}

}  // namespace test_adaptive_sampling
