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
  double best = 0;
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
    std::vector<double> mean(r[0].rgb.size());
    for (size_t i = 0; i < mean.size(); ++i) mean[i] = 0.5 * (double(r[0].rgb[i]) + r[1].rgb[i]);
    Pilot p;
    p.integrator = name;
    p.seconds = 0.5 * (r[0].progress.elapsed_seconds + r[1].progress.elapsed_seconds);
    p.rel_mse = 2 * rdv::relative_mse(r[0].rgb, mean);  // E(a - m)^2 = var / 2
    // A pilot with no measurable error (an exact image) is as efficient as can be, not 1/0.
    p.efficiency = 1.0 / (std::max(p.rel_mse, 1e-30) * std::max(p.seconds, 1e-9));
    p.spp = r[0].progress.samples_done;
    choice.pilot_seconds += r[0].progress.elapsed_seconds + r[1].progress.elapsed_seconds;
    if (choice.pilots.empty() || p.efficiency > best) {
      best = p.efficiency;
      choice.integrator = name;
    }
    choice.pilots.push_back(p);
  }
  return choice;
}

}  // namespace rdv_tools
