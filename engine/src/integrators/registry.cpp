#include "integrators/integrator.h"
#include "integrators/bdpt/bdpt.h"
#include "integrators/path/path_tracer.h"

namespace rdv {

std::unique_ptr<Integrator> make_integrator(const RenderSettings &settings, const Scene &scene) {
  if (settings.integrator == "path") return std::make_unique<PathTracer>(scene, settings.max_bounces);
  if (settings.integrator == "bdpt") {
    bdpt::BdptSettings b;
    b.max_bounces = settings.max_bounces;
    b.strategy_s = settings.strategy_s;
    b.strategy_t = settings.strategy_t;
    b.strategy_unweighted = settings.strategy_unweighted;
    b.mis = settings.mis == "balance"             ? bdpt::MisHeuristic::Balance
            : settings.mis == "lafortune_willems" ? bdpt::MisHeuristic::LafortuneWillems
                                                  : bdpt::MisHeuristic::Power;
    return std::make_unique<bdpt::Bdpt>(scene, b);
  }
  fail("render settings: unknown integrator '" + settings.integrator + "' (available: path, bdpt)");
}

RenderSettings RenderSettings::from_params(Params &p) {
  RenderSettings s;
  s.width = p.get_int("width", 640);
  s.height = p.get_int("height", 480);
  if (s.width <= 0 || s.height <= 0 || s.width > 65536 || s.height > 65536)
    fail(p.what() + ": width and height must be between 1 and 65536");
  s.integrator = p.get_string("integrator", "path");
  s.sampler = p.get_string("sampler", "sobol");
  if (s.sampler != "sobol" && s.sampler != "independent")
    fail(p.what() + ": 'sampler' must be sobol or independent, got '" + s.sampler + "'");
  s.time_limit = p.get_float("time_limit", 0);
  if (s.time_limit < 0) fail(p.what() + ": 'time_limit' must not be negative");
  int samples = p.get_int("samples", s.time_limit > 0 ? 0 : 128);
  if (samples < 0) fail(p.what() + ": 'samples' must not be negative");
  s.samples = static_cast<uint32_t>(samples);
  if (s.samples == 0 && s.time_limit <= 0) s.samples = 128;  // always a halt condition
  s.max_bounces = p.get_int("max_bounces", 12);
  if (s.max_bounces < 0 || s.max_bounces > 1024) fail(p.what() + ": 'max_bounces' must be in 0..1024");
  s.seed = static_cast<uint32_t>(p.get_int("seed", 0));
  s.threads = p.get_int("threads", 0);
  if (s.threads < 0) fail(p.what() + ": 'threads' must not be negative");
  s.clamp = p.get_float("clamp", 0);
  if (s.clamp < 0) fail(p.what() + ": 'clamp' must not be negative");
  s.filter_width = clampf(p.get_float("filter_width", 1.5f), 0.01f, 10.0f);
  auto strategy = p.get_floats("strategy", 2, {-1, -1});
  s.strategy_s = int(strategy[0]);
  s.strategy_t = int(strategy[1]);
  if ((s.strategy_s >= 0) != (s.strategy_t >= 1) && !(s.strategy_s < 0 && s.strategy_t < 0))
    fail(p.what() + ": 'strategy' must be [s, t] with s >= 0 and t >= 1");
  s.strategy_unweighted = p.get_bool("strategy_unweighted", false);
  s.mis = p.get_string("mis", "power");
  if (s.mis != "power" && s.mis != "balance" && s.mis != "lafortune_willems")
    fail(p.what() + ": 'mis' must be power, balance or lafortune_willems, got '" + s.mis + "'");
  s.border = {0, 0, s.width, s.height};
  auto b = p.get_floats("border", 4, {0, 0, float(s.width), float(s.height)});
  s.border = {std::max(0, int(b[0])), std::max(0, int(b[1])), std::min(s.width, int(b[2])), std::min(s.height, int(b[3]))};
  if (s.border.width() <= 0 || s.border.height() <= 0) fail(p.what() + ": 'border' is empty");
  p.check_all_used();
  return s;
}

}  // namespace rdv
