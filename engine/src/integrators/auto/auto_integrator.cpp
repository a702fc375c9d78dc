#include "integrators/auto/auto_integrator.h"
#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>
#include "core/error.h"
#include "film/film.h"
#include "film/image_error.h"
#include "integrators/mlt/path_space.h"
#include "render/render_control.h"

namespace rdv {

namespace {

double relative_square(double d, double reference) {
  return d * d / (reference * reference + kRelativeMseEpsilon);
}

}  // namespace

std::vector<double> errors_against_each_other(const std::vector<std::vector<float>> &images,
                                              const std::vector<double> &reference,
                                              const std::vector<bool> &has_samples) {
  std::vector<size_t> usable;
  for (size_t c = 0; c < images.size(); ++c)
    if (has_samples[c]) usable.push_back(c);
  std::vector<double> errors(images.size(), -1.0);
  const size_t n = usable.size();
  if (n < 3 || reference.empty()) return errors;
  std::vector<double> sums(n, 0.0);
  double total = 0;
  for (size_t a = 0; a < n; ++a)
    for (size_t b = a + 1; b < n; ++b) {
      const std::vector<float> &x = images[usable[a]], &y = images[usable[b]];
      double sum = 0;
      for (size_t i = 0; i < x.size(); ++i) sum += relative_square(double(x[i]) - y[i], reference[i]);
      const double d = sum / double(x.size());
      sums[a] += d;
      sums[b] += d;
      total += d;
    }
  for (size_t a = 0; a < n; ++a) {
    const double v = (sums[a] - total / double(n - 1)) / double(n - 2);
    errors[usable[a]] = std::max(0.0, v);
  }
  return errors;
}

std::string AutoChoice::json() const {
  nlohmann::json p = nlohmann::json::array();
  for (const AutoPilot &x : pilots)
    p.push_back({{"integrator", x.integrator}, {"seconds", x.seconds}, {"rel_mse", x.rel_mse},
                 {"rel_mse_own", x.rel_mse_own}, {"rel_mse_cross", x.rel_mse_cross},
                 {"efficiency", x.efficiency}, {"spp", x.spp}});
  nlohmann::json j = {{"pilot_seconds", pilot_seconds}, {"pilots", p}};
  j["integrator"] = integrator.empty() ? nlohmann::json(nullptr) : nlohmann::json(integrator);
  if (extended) j["time_limit_extended"] = true;
  if (!left_out.empty()) j["left_out"] = left_out;
  return j.dump();
}

AutoIntegrator::AutoIntegrator(const Scene &scene, const RenderSettings &settings)
    : scene_(scene), settings_(settings), pick_settings_(settings) {
  if (!(settings.time_limit > 0))
    fail("render settings: integrator 'auto' picks by error x time: it needs a time limit ('time_limit')");
  if (settings.auto_candidates.empty()) fail("render settings: integrator 'auto' has no candidates");
  // Path-space mlt does not render every scene (PathSpace::unsupported): a candidate
  // that would refuse it is left out, with the reason, instead of failing the render. A
  // warning when the user named the candidates; among the defaults (a Blender scene's
  // Clamp Indirect 10 leaves mlt out) the choice's stats say why.
  std::vector<std::string> &candidates = settings_.auto_candidates;
  const bool named = candidates != RenderSettings().auto_candidates;
  for (auto it = candidates.begin(); it != candidates.end();) {
    const std::string why = *it == "mlt" ? mlt::PathSpace::unsupported(scene, settings) : "";
    if (why.empty()) {
      ++it;
      continue;
    }
    if (named) scene.warn("integrator auto: candidate mlt left out: " + why);
    left_out_.push_back(*it + ": " + why);
    it = candidates.erase(it);
  }
  if (candidates.empty())
    fail("render settings: integrator 'auto': no candidate can render this scene (mlt: see the warning)");
}

AutoChoice AutoIntegrator::choose(RenderContext &ctx) {
  const std::vector<std::string> &candidates = settings_.auto_candidates;
  const double each = settings_.time_limit * kPilotFraction / double(candidates.size());
  const Rect &region = settings_.border;
  const size_t values = size_t(region.width()) * size_t(region.height()) * 3;
  AutoChoice choice;
  choice.left_out = left_out_;
  std::vector<std::vector<float>> images;    // each candidate's pilot
  std::vector<double> pooled(values, 0.0);  // the mean of every pilot image
  std::vector<double> own;                   // each pilot's estimate of its own error; < 0: none
  std::vector<float> rgba(values / 3 * 4);
  for (const std::string &name : candidates) {
    RenderSettings s = settings_;
    s.integrator = name;
    s.samples = 0;
    s.time_limit = each;
    s.noise_target = 0;    // a pilot runs its whole time
    s.noise_pass = true;   // and keeps the half images that estimate its noise
    s.adaptive_sampling = false;
    AutoPilot pilot;
    pilot.integrator = name;
    Film film(settings_.width, settings_.height, region, s.estimates_noise());
    // A shadow catcher's pass costs the pilots what it costs the render (its copies), and
    // the pilots' images are the Combined the render shows.
    if (ctx.film.has_shadow_catcher()) film.keep_shadow_catcher(ctx.film.catcher_display());
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
    std::vector<float> image(values);
    for (size_t p = 0; p < values / 3; ++p)
      for (int c = 0; c < 3; ++c) {
        image[p * 3 + c] = rgba[p * 4 + c];
        pooled[p * 3 + c] += rgba[p * 4 + c] / double(candidates.size());
      }
    // From the pilot's two independent half images (film/noise_estimate.h; for Metropolis
    // its odd and even chains): negative while a half has no sample.
    const double estimate = film.relative_mse_estimate();
    own.push_back(std::isfinite(estimate) ? estimate : -1.0);
    pilot.seconds = control.elapsed();
    pilot.spp = film.frame_state().samples;
    choice.pilot_seconds += control.elapsed();
    images.push_back(std::move(image));
    choice.pilots.push_back(pilot);
  }
  std::vector<bool> has_samples;
  for (const AutoPilot &p : choice.pilots) has_samples.push_back(p.spp > 0);
  const std::vector<double> cross = errors_against_each_other(images, pooled, has_samples);
  double best = 0;
  for (size_t c = 0; c < candidates.size(); ++c) {
    AutoPilot &p = choice.pilots[c];
    p.rel_mse_own = own[c];
    p.rel_mse_cross = cross[c];
    // A pilot's halves show only the paths it found: one that missed a rare caustic
    // looks converged, but its image differs from the others' by that caustic. The
    // larger estimate is its error.
    p.rel_mse = std::max(own[c], cross[c]);
    // A pilot with no measurable error (an exact image) is as efficient as can be, not 1/0;
    // but one without a sample (Metropolis still in its bootstrap) or without any
    // estimate measured nothing.
    p.efficiency = p.spp == 0 || p.rel_mse < 0 ? 0.0 : 1.0 / (std::max(p.rel_mse, 1e-30) * std::max(p.seconds, 1e-9));
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
