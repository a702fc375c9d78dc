// Progressive reads while rendering (rdv_session_read_film promises they are safe): a
// reader thread polls the film through the C ABI, as the add-on's viewport and final
// render do, while BDPT renders the caustic scene by light tracing alone (strategy
// s = 2, t = 1, unweighted: direct light, every pixel a splat) and in full (its caustic
// only light paths carry), and PSSMLT (all splats). Every read must show a frame whose
// splats are scaled for that frame: its mean within noise of the final image's mean.
// Built with -DRDV_SANITIZE=thread (README.md, Sanitizer builds), the same test checks
// that the reads are race-free.
#include <gtest/gtest.h>
#include <atomic>
#include <chrono>
#include <cmath>
#include <nlohmann/json.hpp>
#include <thread>
#include "render_helpers.h"

namespace test_progressive_reads {

using namespace rdv;

namespace {

constexpr int kWidth = 48, kHeight = 36;

double image_mean(const std::vector<float> &rgba) {
  double s = 0;
  for (size_t i = 0; i < rgba.size(); i += 4) s += double(rgba[i]) + rgba[i + 1] + rgba[i + 2];
  return s / double(rgba.size() / 4);
}

std::string caustic_scene() {
  nlohmann::json scene = test::load_scene("caustic.json");
  scene["settings"]["width"] = kWidth;
  scene["settings"]["height"] = kHeight;
  return scene.dump();
}

// Standard deviation of the image mean at `samples` (per pixel), from renders with
// `runs` seeds.
double mean_deviation(const std::string &scene, const nlohmann::json &settings, int samples, int runs) {
  std::vector<double> means;
  for (int k = 0; k < runs; ++k) {
    nlohmann::json s = settings;
    s.update({{"samples", samples}, {"seed", 1000 + k}, {"threads", 2}});
    test::Image img = test::render_json(scene, s.dump());
    means.push_back(image_mean(img.rgba));
  }
  double m = 0, v = 0;
  for (double x : means) m += x / runs;
  for (double x : means) v += (x - m) * (x - m) / (runs - 1);
  return std::sqrt(v);
}

struct Read {
  double amount;  // samples per pixel (MLT: mutations per pixel) the frame has at least
  double mean;
  bool finite;
};

// One render with a reader polling the film until it halts; returns the reads and
// the final image's mean.
std::vector<Read> poll_while_rendering(const std::string &scene_json, const nlohmann::json &render, int samples,
                                       double &final_mean) {
  rdv_scene *scene = nullptr;
  rdv_scene_create(&scene);
  auto loaded = rdv_tools::load_scene_json(scene_json, ".", scene);
  EXPECT_TRUE(loaded.problems.empty());
  nlohmann::json settings = nlohmann::json::parse(loaded.settings_json);
  settings.update(render);
  settings.update({{"samples", samples}, {"seed", 7}, {"threads", 2}});
  const std::string integrator = render["integrator"];
  rdv_session *session = nullptr;
  EXPECT_EQ(rdv_session_create(scene, settings.dump().c_str(), &session), RDV_OK) << rdv_last_error();
  const bool mlt = integrator == "pssmlt" || integrator == "mmlt";
  std::vector<Read> reads;
  std::vector<float> rgba(size_t(kWidth) * kHeight * 4);
  rdv_session_start(session);
  for (;;) {
    // What the frame holds at least: published before the frame a read may show.
    rdv_progress p{};
    rdv_session_progress(session, &p);
    double amount = p.samples_done;
    if (mlt) {
      const char *text = nullptr;
      rdv_session_stats(session, &text);
      nlohmann::json stats = nlohmann::json::parse(text);
      amount = stats.value("mutations", 0.0) / (kWidth * kHeight);
    }
    EXPECT_EQ(rdv_session_read_film(session, RDV_PASS_COMBINED, 0, 0, kWidth, kHeight, 1, rgba.data()), RDV_OK);
    bool finite = true;
    for (float v : rgba) finite = finite && std::isfinite(v);
    reads.push_back({amount, image_mean(rgba), finite});
    if (p.finished) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  rdv_session_wait(session);
  EXPECT_EQ(rdv_session_read_film(session, RDV_PASS_COMBINED, 0, 0, kWidth, kHeight, 1, rgba.data()), RDV_OK);
  final_mean = image_mean(rgba);
  rdv_session_destroy(session);
  rdv_scene_destroy(scene);
  return reads;
}

// Reads of frames with at least `min_amount` samples: |mean - final| <= 6 sigma, sigma
// the deviation at `ref_amount` from 16 seeds, scaled by sqrt(ref / amount) (Sobol
// samples and longer chains do no worse than independent ones). False alarms: a 6-sigma
// deviation of a normal mean has probability 2e-9 per read; with sigma itself estimated
// from 16 runs (and the frames' means nested in the final one), below 1e-4 per read,
// and the verdict for a given schedule of reads is fixed by the seeds.
void check_reads(const nlohmann::json &render, int samples, int ref_samples, double min_amount) {
  const std::string scene = caustic_scene();
  const std::string integrator = render["integrator"];
  const double sigma_ref = mean_deviation(scene, render, ref_samples, 16);
  double final_mean = 0;
  std::vector<Read> reads = poll_while_rendering(scene, render, samples, final_mean);
  ASSERT_GT(final_mean, 0);
  int checked = 0, worst_read = -1;
  double worst_z = 0;
  for (size_t i = 0; i < reads.size(); ++i) {
    const Read &r = reads[i];
    EXPECT_TRUE(r.finite) << "read " << i;
    if (r.amount < min_amount) continue;
    double sigma = sigma_ref * std::sqrt(double(ref_samples) / r.amount);
    double z = std::fabs(r.mean - final_mean) / sigma;
    if (z > worst_z) { worst_z = z; worst_read = int(i); }
    ++checked;
  }
  std::printf("%s: %zu reads, %d checked, final mean %.5f, sigma at %d spp %.5f (%.2f%%), worst |z| %.2f (read %d)\n",
              integrator.c_str(), reads.size(), checked, final_mean, ref_samples, sigma_ref,
              100 * sigma_ref / final_mean, worst_z, worst_read);
  EXPECT_GE(checked, 10) << "the render ended before the reader saw enough frames";
  EXPECT_LE(worst_z, 6.0) << "read " << worst_read << " of " << reads.size() << ": mean "
                          << reads[size_t(worst_read)].mean << " at " << reads[size_t(worst_read)].amount
                          << " samples per pixel, final " << final_mean;
}

}  // namespace

TEST(ProgressiveReads, BdptLightTracingFramesAreScaledForTheirSamples) {
  check_reads({{"integrator", "bdpt"}, {"strategy", {2, 1}}, {"strategy_unweighted", true}}, 512, 4, 1);
}

TEST(ProgressiveReads, BdptFramesAreScaledForTheirSamples) { check_reads({{"integrator", "bdpt"}}, 512, 4, 1); }

TEST(ProgressiveReads, PssmltFramesAreScaledForTheirMutations) { check_reads({{"integrator", "pssmlt"}}, 256, 4, 1); }

}  // namespace test_progressive_reads
