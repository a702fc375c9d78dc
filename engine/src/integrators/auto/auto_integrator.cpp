#include "integrators/auto/auto_integrator.h"
#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>
#include "core/error.h"
#include "film/film.h"
#include "film/image_error.h"
#include "render/render_control.h"

namespace rdv {

std::string AutoChoice::json() const {
  nlohmann::json p = nlohmann::json::array();
  for (const AutoPilot &x : pilots)
    p.push_back({{"integrator", x.integrator}, {"seconds", x.seconds}, {"rel_mse", x.rel_mse},
                 {"efficiency", x.efficiency}, {"spp", x.spp}});
  nlohmann::json j = {{"pilot_seconds", pilot_seconds}, {"pilots", p}};
  j["integrator"] = integrator.empty() ? nlohmann::json(nullptr) : nlohmann::json(integrator);
  if (extended) j["time_limit_extended"] = true;
  return j.dump();
}

AutoIntegrator::AutoIntegrator(const Scene &scene, const RenderSettings &settings)
    : scene_(scene), settings_(settings), pick_settings_(settings) {
  if (!(settings.time_limit > 0))
    fail("render settings: integrator 'auto' picks by error x time: it needs a time limit ('time_limit')");
  if (settings.auto_candidates.empty()) fail("render settings: integrator 'auto' has no candidates");
}

AutoChoice AutoIntegrator::choose(RenderContext &ctx) {
  const std::vector<std::string> &candidates = settings_.auto_candidates;
  const double each = settings_.time_limit * kPilotFraction / (2.0 * candidates.size());
  const Rect &region = settings_.border;
  const size_t values = size_t(region.width()) * size_t(region.height()) * 3;
  AutoChoice choice;
  std::vector<std::vector<float>> differences;  // a - b per candidate
  std::vector<double> pooled(values, 0.0);      // the sum of every pilot image
  std::vector<float> rgba(values / 3 * 4);
  for (const std::string &name : candidates) {
    RenderSettings s = settings_;
    s.integrator = name;
    s.samples = 0;
    s.time_limit = each;
    s.noise_target = 0;  // a pilot runs its whole time: the estimate needs equal times
    AutoPilot pilot;
    pilot.integrator = name;
    pilot.spp = UINT32_MAX;
    std::vector<float> d(values);
    for (int i = 0; i < 2; ++i) {
      s.seed = settings_.seed + uint32_t(i);
      Film film(settings_.width, settings_.height, region, s.estimates_noise());
      RenderControl control(each, 0);
      control.follow(ctx.control);  // a cancel of the render stops its pilots
      std::unique_ptr<Integrator> integrator = make_integrator(s, scene_);
      RenderContext pilot_ctx{ctx.scene, s, film, ctx.filter, control, ctx.arena};
      control.start();
      integrator->render(pilot_ctx);
      control.finish();
      ctx.control.add_rays(control.rays());
      ctx.control.add_dropped(control.dropped());
      if (ctx.control.cancel_requested()) return choice;
      film.read(RDV_PASS_COMBINED, region.x0, region.y0, region.width(), region.height(), true, rgba.data());
      for (size_t p = 0; p < values / 3; ++p)
        for (int c = 0; c < 3; ++c) {
          const float v = rgba[p * 4 + c];
          pooled[p * 3 + c] += v;
          d[p * 3 + c] = i == 0 ? v : d[p * 3 + c] - v;
        }
      pilot.seconds += 0.5 * control.elapsed();
      pilot.spp = std::min(pilot.spp, film.frame_state().samples);
      choice.pilot_seconds += control.elapsed();
    }
    differences.push_back(std::move(d));
    choice.pilots.push_back(pilot);
  }
  // Every pilot is an unbiased image of the same scene: their mean is the least noisy
  // reference at hand for relMSE's denominator (a pilot's own noisy mean there makes
  // very noisy pilots all look alike: (a - m)^2 / m^2 is at most ~1 per value).
  for (double &v : pooled) v /= 2.0 * candidates.size();
  double best = 0;
  for (size_t c = 0; c < candidates.size(); ++c) {
    AutoPilot &p = choice.pilots[c];
    double sum = 0;
    for (size_t i = 0; i < values; ++i)
      sum += double(differences[c][i]) * differences[c][i] / (pooled[i] * pooled[i] + kRelativeMseEpsilon);
    p.rel_mse = values == 0 ? 0.0 : sum / double(values) / 2;  // E(a - b)^2 = 2 var
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

void AutoIntegrator::render(RenderContext &ctx) {
  AutoChoice choice = choose(ctx);
  if (choice.integrator.empty()) {  // cancelled during the pilots
    std::lock_guard<std::mutex> lock(mutex_);
    choice_ = choice;
    return;
  }
  // Slow pilots (a Metropolis bootstrap that outlasts its pilot time) must not leave the
  // pick without time: it renders at least kLeastRenderFraction of the limit.
  const double least = kLeastRenderFraction * settings_.time_limit;
  if (ctx.control.elapsed() + least > settings_.time_limit) {
    ctx.control.extend_time_limit(ctx.control.elapsed() + least);
    choice.extended = true;
  }
  pick_settings_.integrator = choice.integrator;
  std::unique_ptr<Integrator> pick = make_integrator(pick_settings_, scene_);
  Integrator *integrator = pick.get();
  {
    std::lock_guard<std::mutex> lock(mutex_);
    choice_ = choice;
    pick_ = std::move(pick);
  }
  RenderContext pick_ctx{ctx.scene, pick_settings_, ctx.film, ctx.filter, ctx.control, ctx.arena};
  integrator->render(pick_ctx);
}

std::string AutoIntegrator::stats_json() const {
  std::lock_guard<std::mutex> lock(mutex_);
  nlohmann::json j = pick_ ? nlohmann::json::parse(pick_->stats_json()) : nlohmann::json::object();
  j["auto"] = nlohmann::json::parse(choice_.json());
  return j.dump();
}

}  // namespace rdv
