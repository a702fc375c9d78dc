// integrator "auto": short pilot renders of each candidate integrator, efficiency =
// 1 / (estimated error x time), and the most efficient one renders the rest of the time
// budget into the session's film. The error of a pilot is estimated without a reference,
// from two independent renders a, b (seeds s and s + 1) of the same time:
// mean (a - b)^2 / (R^2 + 0.01) / 2, with R the mean of every candidate's pilots (all
// unbiased images of the scene). Independent runs make the estimate honest for
// Metropolis too, whose samples within one run are correlated. docs/trade.md measures
// the picks against the study.
#pragma once
#include <memory>
#include <mutex>
#include <string>
#include <vector>
#include "integrators/integrator.h"

namespace rdv {

struct AutoPilot {
  std::string integrator;
  double seconds = 0;     // one of its two renders
  double rel_mse = 0;     // estimated error of one render
  double efficiency = 0;  // 1 / (rel_mse x seconds); 0 when a pilot made no sample
  uint32_t spp = 0;       // the fewer of its two renders
};

struct AutoChoice {
  std::string integrator;  // empty until the pilots are done
  std::vector<AutoPilot> pilots;
  double pilot_seconds = 0;  // all pilots together
  bool extended = false;     // the pilots overran: the time limit grew to give the pick its share
  std::string json() const;
};

class AutoIntegrator final : public Integrator {
 public:
  // The share of the time limit the pilots get (two renders per candidate).
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
  mutable std::mutex mutex_;      // guards choice_ and pick_ for stats_json()
  AutoChoice choice_;
  std::unique_ptr<Integrator> pick_;
};

}  // namespace rdv
