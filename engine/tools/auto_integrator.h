// `--integrator auto`: short pilot renders of each candidate integrator, efficiency =
// 1 / (estimated error x time), and the best one renders the rest of the time budget.
// The error of a pilot is estimated without a reference, from two independent renders
// a, b (seeds s and s + 1) of the same time: mean (a - b)^2 / (R^2 + 0.01) / 2, with R
// the mean of every candidate's pilots (all unbiased images of the scene). Independent
// runs make the estimate honest for Metropolis too, whose samples within one run are
// correlated.
#pragma once
#include <nlohmann/json.hpp>
#include <string>
#include <vector>
#include "rendezvous.h"

namespace rdv_tools {

struct Pilot {
  std::string integrator;
  double seconds = 0;     // one of its two renders
  double rel_mse = 0;     // estimated error of one render
  double efficiency = 0;  // 1 / (rel_mse x seconds); 0 when a pilot made no sample
  uint32_t spp = 0;       // the fewer of its two renders
};

struct AutoChoice {
  std::string integrator;
  std::vector<Pilot> pilots;
  double pilot_seconds = 0;  // all pilots together
  nlohmann::json to_json() const;
};

// The candidates when none are given.
const std::vector<std::string> &auto_candidates();

// Pilots of `candidates` on `scene` with `settings` (its time limit is the whole budget;
// pilots take `pilot_fraction` of it, two renders per candidate). Throws
// std::runtime_error naming the candidate when a pilot fails, and when settings have no
// time limit.
AutoChoice choose_integrator(rdv_scene *scene, const nlohmann::json &settings,
                             const std::vector<std::string> &candidates = auto_candidates(),
                             double pilot_fraction = 0.1);

}  // namespace rdv_tools
