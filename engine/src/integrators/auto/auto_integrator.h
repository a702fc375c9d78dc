// integrator "auto": short pilot renders of each candidate integrator, efficiency =
// 1 / (estimated error x time), and the most efficient one renders the rest of the time
// budget into the session's film. The error of a pilot is estimated without a reference,
// twice: from its two independent half images (film/noise_estimate.h: for Metropolis its
// odd and even chains, as its samples are correlated), and from how the candidates'
// pilots (all unbiased images of the scene) differ from each other, which also shows
// paths a candidate's pilot never found; the larger counts. docs/trade.md measures the
// picks against the study.
#pragma once
#include <memory>
#include <mutex>
#include <string>
#include <vector>
#include "integrators/integrator.h"

namespace rdv {

struct AutoPilot {
  std::string integrator;
  double seconds = 0;        // its pilot render
  double rel_mse = 0;        // the pilot's estimated error: the larger of the two below
  double rel_mse_own = 0;    // from its half images; -1: no estimate (a half without samples)
  double rel_mse_cross = 0;  // against the other candidates' pilots; -1: fewer than 3 with samples
  double efficiency = 0;     // 1 / (rel_mse x seconds); 0 when a pilot made no sample
  uint32_t spp = 0;
};

struct AutoChoice {
  std::string integrator;  // empty until the pilots are done
  std::vector<AutoPilot> pilots;
  double pilot_seconds = 0;  // all pilots together
  bool extended = false;     // the pilots overran: the time limit grew to give the pick its share
  std::vector<std::string> left_out;  // candidates that cannot render the scene: "name: why"
  std::string json() const;
};

// Each candidate's pilot error from how its image differs from the other candidates'
// (the "three-cornered hat" of clock comparisons): the pilots are independent, so
// D_ij = relMSE(x_i - x_j) (over reference^2 + 0.01) estimates V_i + V_j, V a pilot's error.
// Least squares over every pair gives V_i = (S_i - T / (n - 1)) / (n - 2), S_i the sum of
// candidate i's D_ij and T the sum over all pairs. Unlike a pilot's own estimate this sees
// what a candidate did not find (a rare caustic no sample of it hit). Needs three
// candidates with samples; the others get -1 (no evidence beyond their own pilot).
std::vector<double> errors_against_each_other(const std::vector<std::vector<float>> &images,
                                              const std::vector<double> &reference,
                                              const std::vector<bool> &has_samples);

class AutoIntegrator final : public Integrator {
 public:
  // The share of the time limit the pilots get (one render per candidate).
  static constexpr double kPilotFraction = 0.1;
  // The least share of the time limit the pick renders for, even after slow pilots.
  static constexpr double kLeastRenderFraction = 0.05;

  AutoIntegrator(const Scene &scene, const RenderSettings &settings);
  void render(RenderContext &ctx) override;
  // {"auto": the choice and its evidence (AutoChoice::json), then the pick's own figures}.
  std::string stats_json() const override;
  // The pilots only (tests, the CLI's --summary): what render() would choose.
  AutoChoice choose(RenderContext &ctx);

 private:
  const Scene &scene_;
  RenderSettings settings_;
  RenderSettings pick_settings_;  // settings_ with the chosen integrator
  std::vector<std::string> left_out_;  // candidates the scene rules out ("name: why")
  mutable std::mutex mutex_;      // guards choice_ and pick_ for stats_json()
  AutoChoice choice_;
  std::unique_ptr<Integrator> pick_;
};

}  // namespace rdv
