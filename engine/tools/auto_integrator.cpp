#include "auto_integrator.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include "equal_time.h"
#include "film/image_error.h"

namespace rdv_tools {

using nlohmann::json;

const std::vector<std::string> &auto_candidates() {
  static const std::vector<std::string> names = {"path", "bdpt", "pssmlt", "mmlt"};
  return names;
}

json AutoChoice::to_json() const {
  json p = json::array();
  for (const Pilot &x : pilots)
    p.push_back({{"integrator", x.integrator}, {"seconds", x.seconds}, {"rel_mse", x.rel_mse},
                 {"efficiency", x.efficiency}, {"spp", x.spp}});
  return {{"integrator", integrator}, {"pilot_seconds", pilot_seconds}, {"pilots", p}};
}

AutoChoice choose_integrator(rdv_scene *scene, const json &settings, const std::vector<std::string> &candidates,
                             double pilot_fraction) {
  const double budget = settings.value("time_limit", 0.0);
  if (!(budget > 0) || !std::isfinite(budget))
    throw std::runtime_error("integrator auto picks by error x time: it needs a time limit (time_limit, --time)");
  if (candidates.empty()) throw std::runtime_error("integrator auto: no candidates");
  const double each = budget * pilot_fraction / (2.0 * candidates.size());
  const int seed = settings.value("seed", 0);
  AutoChoice choice;
  std::vector<std::vector<float>> differences;  // a - b per candidate
  std::vector<double> pooled;                   // the sum of every pilot image
  for (const std::string &name : candidates) {
    json s = settings;
    s.erase("noise_target");  // a pilot runs its whole time: the estimate needs equal times
    s["integrator"] = name;
    s["samples"] = 0;
    s["time_limit"] = each;
    TimedRender r[2];
    for (int i = 0; i < 2; ++i) {
      s["seed"] = seed + i;
      try {
        r[i] = render_loaded(scene, s);
      } catch (const std::exception &e) {
        throw std::runtime_error("integrator auto: pilot of " + name + ": " + e.what());
      }
    }
    pooled.resize(r[0].rgb.size(), 0.0);
    std::vector<float> d(r[0].rgb.size());
    for (size_t i = 0; i < d.size(); ++i) {
      d[i] = r[0].rgb[i] - r[1].rgb[i];
      pooled[i] += double(r[0].rgb[i]) + r[1].rgb[i];
    }
    differences.push_back(std::move(d));
    Pilot p;
    p.integrator = name;
    p.seconds = 0.5 * (r[0].progress.elapsed_seconds + r[1].progress.elapsed_seconds);
    p.spp = std::min(r[0].progress.samples_done, r[1].progress.samples_done);
    choice.pilot_seconds += r[0].progress.elapsed_seconds + r[1].progress.elapsed_seconds;
    choice.pilots.push_back(p);
  }
  // Every pilot is an unbiased image of the same scene: their mean is the least noisy
  // reference at hand for relMSE's denominator (a pilot's own noisy mean there makes
  // very noisy pilots all look alike: (a - m)^2 / m^2 is at most ~1 per value).
  for (double &v : pooled) v /= 2.0 * candidates.size();
  double best = 0;
  for (size_t c = 0; c < candidates.size(); ++c) {
    Pilot &p = choice.pilots[c];
    double sum = 0;
    for (size_t i = 0; i < pooled.size(); ++i)
      sum += double(differences[c][i]) * differences[c][i] / (pooled[i] * pooled[i] + rdv::kRelativeMseEpsilon);
    p.rel_mse = pooled.empty() ? 0.0 : sum / pooled.size() / 2;  // E(a - b)^2 = 2 var
    // A pilot with no measurable error (an exact image) is as efficient as can be, not 1/0;
    // but one without a sample (Metropolis still in its bootstrap) measured nothing.
    p.efficiency = p.spp == 0 ? 0.0 : 1.0 / (std::max(p.rel_mse, 1e-30) * std::max(p.seconds, 1e-9));
    if (c == 0 || p.efficiency > best) {
      best = p.efficiency;
      choice.integrator = p.integrator;
    }
  }
  return choice;
}

}  // namespace rdv_tools
