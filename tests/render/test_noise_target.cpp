// The noise-target halt and the noise estimate it halts on (film/noise_estimate.h):
// honest against the true error. Each scene is rendered once long as the reference;
// renders that halt at a noise target are then compared with it, and the true relative
// MSE at the halt must lie within 2x of the target, both ways, for every fixed seed,
// Metropolis included. The reference's own error (its estimate, under a tenth of the
// target) is subtracted. Seeds are fixed: each verdict is reproducible.
#include <gtest/gtest.h>
#include <cmath>
#include <map>
#include <nlohmann/json.hpp>
#include <vector>
#include "film/image_error.h"
#include "render_helpers.h"

namespace test_noise_target {

using namespace rdv::test;
using nlohmann::json;

namespace {

std::vector<float> rgb(const Image &img) {
  std::vector<float> out;
  out.reserve(size_t(img.width) * img.height * 3);
  for (size_t i = 0; i < size_t(img.width) * img.height; ++i)
    for (int c = 0; c < 3; ++c) out.push_back(img.rgba[4 * i + c]);
  return out;
}

// The long render the halts are measured against, once per process for a scene and its
// settings (BDPT's Cornell box serves BDPT and the three Metropolis integrators).
const Image &reference_render(const json &scene, const json &settings, const json &reference_settings) {
  static std::map<std::string, Image> rendered;
  json r = {{"width", settings["width"]}, {"height", settings["height"]}, {"integrator", settings["integrator"]},
            {"max_bounces", settings["max_bounces"]}};
  r.update(reference_settings);
  r["seed"] = 1000;
  r["noise_pass"] = true;  // the reference's own error, to take out of the measured one
  const std::string key = scene.dump() + '\n' + r.dump();
  auto it = rendered.find(key);
  if (it == rendered.end()) it = rendered.emplace(key, render_json(scene.dump(), r.dump())).first;
  return it->second;
}

// Renders the scene at the noise target with each seed; returns the worst ratio of true
// relative MSE over target (furthest from 1, in log), printing every figure.
void expect_honest_halt(const std::string &what, const json &scene, json settings, const json &reference_settings,
                        double target, std::vector<uint32_t> seeds) {
  const Image &reference = reference_render(scene, settings, reference_settings);
  ASSERT_TRUE(reference.all_finite());
  const double reference_error = reference.progress.noise_estimate;
  ASSERT_TRUE(reference_error >= 0 && reference_error < 0.1 * target) << what << ": reference " << reference_error;
  const std::vector<float> ref = rgb(reference);
  for (uint32_t seed : seeds) {
    settings["seed"] = seed;
    settings["noise_target"] = target;
    Image img = render_json(scene.dump(), settings.dump());
    ASSERT_TRUE(img.all_finite());
    EXPECT_EQ(img.progress.noise_reached, 1) << what << " seed " << seed;
    const double measured = rdv::relative_mse(rgb(img), ref);
    // The reference's noise is in `measured` too (independent of the render's).
    const double truth = measured - reference_error;
    const double ratio = truth / target;
    std::printf("[ noise target ] %-18s seed %2u: target %.3g, estimate %.3g, true %.3g (ratio %.2f) at %u spp\n",
                what.c_str(), seed, target, img.progress.noise_estimate, truth, ratio, img.progress.samples_done);
    EXPECT_GT(ratio, 0.5) << what << " seed " << seed;
    EXPECT_LT(ratio, 2.0) << what << " seed " << seed;
  }
}

json small(int w, int h, const char *integrator) {
  return {{"width", w}, {"height", h}, {"integrator", integrator}, {"max_bounces", 8}, {"samples", 0}, {"time_limit", 30}};  // the limit: a failure, not a hang
}

}  // namespace

TEST(NoiseTarget, PathCornellBox) {
  expect_honest_halt("cornell path", load_scene("cornell_box.json"), small(32, 32, "path"), {{"samples", 4096}}, 3e-3,
                     {1, 2, 3, 4});
}


TEST(NoiseTarget, BdptCaustic) {
  expect_honest_halt("caustic bdpt", load_scene("caustic.json"), small(32, 32, "bdpt"), {{"samples", 2048}}, 1e-2,
                     {1, 2, 3, 4});
}

// Metropolis: 64 chains, 32 per half image; the reference is BDPT's (one render for BDPT's
// halts and the three Metropolis integrators').
void expect_honest_metropolis_halt(const char *integrator, const json &more = json::object()) {
  json s = small(32, 32, integrator);
  s["mlt_chains"] = 64;
  s["mlt_bootstrap"] = 4;
  s.update(more);
  expect_honest_halt(std::string("cornell ") + integrator + (more.empty() ? "" : " " + more.dump()),
                     load_scene("cornell_box.json"), s, {{"integrator", "bdpt"}, {"samples", 2048}}, 3e-3,
                     {1, 2, 3, 4});
}

// Direct light by path tracing (mlt_direct_samples): its N samples are taken first and do
// not refine, so the estimate must count their noise (the camera halves') with the chains'.
TEST(NoiseTarget, BdptAndMetropolisCornellBox) {
  expect_honest_halt("cornell bdpt", load_scene("cornell_box.json"), small(32, 32, "bdpt"), {{"samples", 2048}}, 3e-3,
                     {1, 2, 3, 4});
  expect_honest_metropolis_halt("pssmlt");
  expect_honest_metropolis_halt("mmlt");
  expect_honest_metropolis_halt("mlt");
  expect_honest_metropolis_halt("mlt", {{"mlt_direct_samples", 256}});
}

// Where a render halts depends on the seed only: passes follow a fixed schedule while
// the noise is estimated, so 1 and 2 threads stop at the same sample with the same image.
TEST(NoiseTarget, SameHaltOnOneAndTwoThreads) {
  json scene = load_scene("cornell_box.json");
  for (const char *integrator : {"path", "bdpt"}) {
    json s = small(24, 24, integrator);
    s["noise_target"] = 0.01;
    s["seed"] = 7;
    s["threads"] = 1;
    Image one = render_json(scene.dump(), s.dump());
    s["threads"] = 2;
    Image two = render_json(scene.dump(), s.dump());
    EXPECT_EQ(one.progress.noise_reached, 1) << integrator;
    EXPECT_EQ(one.progress.samples_done, two.progress.samples_done) << integrator;
    EXPECT_EQ(one.rgba, two.rgba) << integrator;
    EXPECT_EQ(one.noise, two.noise) << integrator;
  }
}

// The Noise pass: the estimated relative error of each pixel, finite and >= 0, whose
// mean square is the frame's estimate; 0 everywhere when the render estimates nothing.
TEST(NoiseTarget, NoisePassMatchesTheEstimate) {
  json s = small(24, 24, "bdpt");
  s["samples"] = 16;
  s["noise_pass"] = true;
  Image img = render_json(load_scene("cornell_box.json").dump(), s.dump());
  double sum = 0;
  for (float v : img.noise) {
    ASSERT_TRUE(std::isfinite(v) && v >= 0);
    sum += double(v) * v;
  }
  const double mean = sum / double(img.noise.size());
  EXPECT_NEAR(mean, img.progress.noise_estimate, 1e-4 * img.progress.noise_estimate);
  EXPECT_GT(mean, 0);
  EXPECT_EQ(img.progress.noise_reached, 0);
  s.erase("noise_pass");
  Image plain = render_json(load_scene("cornell_box.json").dump(), s.dump());
  EXPECT_EQ(plain.progress.noise_estimate, -1);
  for (float v : plain.noise) ASSERT_EQ(v, 0.0f);
}

// A negative or non-finite target is an error naming the setting, not a render.
TEST(NoiseTarget, BadTargetsAreRefused) {
  SceneHandle scene;
  for (const char *settings : {R"({"noise_target": -0.001})", R"({"noise_target": null})",
                               R"({"noise_target": "small"})"}) {
    rdv_session *session = nullptr;
    EXPECT_NE(rdv_session_create(scene.s, settings, &session), RDV_OK) << settings;
    EXPECT_EQ(session, nullptr);
    EXPECT_NE(std::string(rdv_last_error()).find("noise_target"), std::string::npos) << rdv_last_error();
  }
}

}  // namespace test_noise_target
