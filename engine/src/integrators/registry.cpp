#include "integrators/integrator.h"
#include "core/limits.h"
#include "core/log.h"
#include <nlohmann/json.hpp>
#include "integrators/auto/auto_integrator.h"
#include "integrators/bdpt/bdpt.h"
#include "integrators/mlt/metropolis.h"
#include "integrators/path/path_tracer.h"

namespace rdv {

// The film's alpha settings with what the scene adds (its holdouts).
static FilmAlpha film_alpha(const RenderSettings &settings, const Scene &scene) {
  FilmAlpha a = settings.alpha;
  a.holdouts = scene.has_holdouts();
  return a;
}

static bdpt::BdptSettings bdpt_settings(const RenderSettings &settings, const Scene &scene) {
  bdpt::BdptSettings b;
  b.max_bounces = settings.max_bounces;
  b.limits = settings.limits;
  b.alpha = film_alpha(settings, scene);
  b.strategy_s = settings.strategy_s;
  b.strategy_t = settings.strategy_t;
  b.strategy_unweighted = settings.strategy_unweighted;
  b.mis = settings.mis == "balance"             ? bdpt::MisHeuristic::Balance
          : settings.mis == "lafortune_willems" ? bdpt::MisHeuristic::LafortuneWillems
                                                : bdpt::MisHeuristic::Power;
  if (b.mis == bdpt::MisHeuristic::LafortuneWillems && settings.limits.filter_glossy > 0) {
    // Their split gives each strategy a share whether or not it can make the path, and
    // Filter Glossy takes the light-walk strategies from some paths (filter_glossy.h).
    scene.warn("mis 'lafortune_willems' cannot be combined with filter_glossy (Filter Glossy): BDPT uses the "
                "power heuristic");
    b.mis = bdpt::MisHeuristic::Power;
  }
  if (b.mis == bdpt::MisHeuristic::LafortuneWillems && scene.has_mixed_visibility()) {
    // Likewise mixed ray visibility takes the light-walk strategies from some paths (bdpt.h).
    scene.warn(scene.mixed_visibility_object() + " is seen by some kinds of ray but not by others (ray visibility): "
               "mis 'lafortune_willems' cannot tell which strategies that rules out, so BDPT uses the power heuristic");
    b.mis = bdpt::MisHeuristic::Power;
  }
  return b;
}

std::unique_ptr<Integrator> make_integrator(const RenderSettings &settings, const Scene &scene) {
  if (settings.integrator == "path") return std::make_unique<PathTracer>(scene, settings.max_bounces, settings.limits, film_alpha(settings, scene));
  if (settings.clamp > 0 && (settings.integrator == "mmlt" || settings.integrator == "mlt"))
    scene.warn("'clamp' (the sample clamp) is not applied by " + settings.integrator +
                ": it caps a camera sample's value, which " + settings.integrator +
                "'s states (one strategy, or one path) do not have; path, bdpt and pssmlt apply it");
  if (settings.integrator == "bdpt") return std::make_unique<bdpt::Bdpt>(scene, bdpt_settings(settings, scene));
  if (settings.integrator == "pssmlt" || settings.integrator == "mmlt") {
    mlt::MltSettings m;
    m.multiplexed = settings.integrator == "mmlt";
    m.large_step_probability = settings.mlt_large_step;
    m.bootstrap_per_pixel = settings.mlt_bootstrap;
    m.chains = settings.mlt_chains;
    m.step_size = settings.mlt_step_size;
    m.relative_target = settings.relative_mlt_target(false);
    return std::make_unique<mlt::Metropolis>(scene, settings, bdpt_settings(settings, scene), m);
  }
  if (settings.integrator == "mlt") {
    std::string why = mlt::PathSpace::unsupported(scene, settings);
    if (!why.empty()) fail("render settings: integrator mlt: " + why);
    mlt::MltSettings m;
    m.path_space = true;
    m.large_step_probability = settings.mlt_large_step;
    m.bootstrap_per_pixel = settings.mlt_bootstrap;
    m.chains = settings.mlt_chains;
    m.relative_target = settings.relative_mlt_target(true);
    static_assert(sizeof(settings.mlt_mutations) / sizeof(float) == mlt::kWeightedMutations);
    for (int i = 0; i < mlt::kWeightedMutations; ++i) m.mutations.weights[i] = settings.mlt_mutations[i];
    // Veach's lens perturbation: 0.1 pixel to a tenth of the image.
    m.mutations.lens[0] = 0.1f;
    m.mutations.lens[1] = std::max(1.0f, 0.1f * float(std::max(settings.width, settings.height)));
    for (int i = 0; i < 2; ++i) {
      m.mutations.distance[i] = settings.mlt_propagation_range[i] * scene.bounding_radius();
      m.mutations.angle[i] = settings.mlt_scattering_angle[i];
      m.mutations.caustic[i] = settings.mlt_caustic_angle[i];
    }
    m.mutations.keep_distances = settings.mlt_keep_distances;
    m.mutations.equiangular = settings.mlt_equiangular;
    m.direct_samples = settings.mlt_direct_samples;
    return std::make_unique<mlt::Metropolis>(scene, settings, bdpt_settings(settings, scene), m);
  }
  if (settings.integrator == "auto") return std::make_unique<AutoIntegrator>(scene, settings);
  fail("render settings: unknown integrator '" + settings.integrator + "' (available: path, bdpt, pssmlt, mmlt, mlt, auto)");
}

// Cycles' Light Paths settings; absent ones are off (no limit, caustics on, no clamp).
// A float setting as a whole number in [lo, hi], clamped before the conversion (a
// float beyond int's range, e.g. a border of 1e30, has no int value).
static int clamped_int(float v, int lo, int hi) { return !(v > float(lo)) ? lo : v >= float(hi) ? hi : int(v); }

static LightPathLimits light_path_limits(Params &p) {
  LightPathLimits l;
  auto bounces = [&](const char *key, int &out) {
    if (!p.has(key)) return;
    out = p.get_int(key, LightPathLimits::kNoLimit);
    if (out < 0 || out > 1024) fail(p.what() + ": '" + key + "' must be in 0..1024");
  };
  bounces("diffuse_bounces", l.diffuse);
  bounces("glossy_bounces", l.glossy);
  bounces("transmission_bounces", l.transmission);
  bounces("volume_bounces", l.volume);
  bounces("transparent_max_bounces", l.transparent);
  l.caustics_reflective = p.get_bool("caustics_reflective", true);
  l.caustics_refractive = p.get_bool("caustics_refractive", true);
  l.clamp_direct = p.get_float("clamp_direct", 0);
  l.clamp_indirect = p.get_float("clamp_indirect", 0);
  if (!(l.clamp_direct >= 0) || !(l.clamp_indirect >= 0))
    fail(p.what() + ": 'clamp_direct' and 'clamp_indirect' must not be negative (0 = off)");
  l.filter_glossy = p.get_float("filter_glossy", 0);
  if (!(l.filter_glossy >= 0) || !std::isfinite(l.filter_glossy))
    fail(p.what() + ": 'filter_glossy' must be finite and not negative (0 = off)");
  l.finish();
  return l;
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
  s.noise_target = p.get_float("noise_target", 0);  // NaN and Inf: "not a finite number"
  if (s.noise_target < 0)
    fail(p.what() + ": 'noise_target' must not be negative (the relative MSE to stop at; 0 = off), got " +
         std::to_string(s.noise_target));
  s.noise_pass = p.get_bool("noise_pass", false);
  s.adaptive_sampling = p.get_bool("adaptive_sampling", false);
  s.adaptive_threshold = p.get_float("adaptive_threshold", s.adaptive_threshold);
  if (!(s.adaptive_threshold > 0))
    fail(p.what() + ": 'adaptive_threshold' must be positive (the relative error at which a pixel stops), got " +
         std::to_string(s.adaptive_threshold));
  int min_samples = p.get_int("adaptive_min_samples", 0);
  if (min_samples < 0) fail(p.what() + ": 'adaptive_min_samples' must not be negative (0 = automatic)");
  s.adaptive_min_samples = uint32_t(min_samples);
  // A time limit or a noise target alone renders until it halts.
  int samples = p.get_int("samples", s.time_limit > 0 || s.noise_target > 0 ? 0 : 128);
  if (samples < 0) fail(p.what() + ": 'samples' must not be negative");
  if (uint32_t(samples) > kMaxSamplesPerPixel)
    fail(p.what() + ": 'samples' is " + std::to_string(samples) + "; at most " + std::to_string(kMaxSamplesPerPixel) +
             " per pixel (the film counts samples in float)",
         RDV_ERROR_LIMIT);
  s.samples = static_cast<uint32_t>(samples);
  if (s.samples == 0 && s.time_limit <= 0 && s.noise_target <= 0) s.samples = 128;  // always a halt condition
  int offset = p.get_int("sample_offset", 0);
  if (offset < 0) fail(p.what() + ": 'sample_offset' must not be negative");
  s.sample_offset = static_cast<uint32_t>(offset);
  s.scene_hash = p.get_string("scene_hash", "");
  s.max_bounces = p.get_int("max_bounces", 12);
  if (s.max_bounces < 0 || s.max_bounces > 1024) fail(p.what() + ": 'max_bounces' must be in 0..1024");
  s.limits = light_path_limits(p);
  s.alpha.film_transparent = p.get_bool("film_transparent", false);
  s.alpha.transparent_glass = p.get_bool("film_transparent_glass", false);
  s.alpha.glass_roughness = p.get_float("film_transparent_roughness", s.alpha.glass_roughness);
  if (!(s.alpha.glass_roughness >= 0 && s.alpha.glass_roughness <= 1))
    fail(p.what() + ": 'film_transparent_roughness' must be in 0..1, got " + std::to_string(s.alpha.glass_roughness));
  s.light_passes = p.get_bool("light_passes", false);
  s.data_passes = p.get_bool("data_passes", false);
  s.denoising_passes = p.get_bool("denoising_passes", false);
  s.shader_aovs = ShaderAovs::parse(p.get_json("aovs"));
  s.cryptomatte = Cryptomatte::parse(p.get_json("cryptomatte"));
  s.shadow_catcher_pass = p.get_bool("shadow_catcher_pass", false);
  s.strategy_passes = p.get_bool("strategy_passes", false);
  s.strategy_passes_max_depth = p.get_int("strategy_passes_max_depth", s.strategy_passes_max_depth);
  if (s.strategy_passes_max_depth < 0 || s.strategy_passes_max_depth > StrategyPasses::kMaxDepth)
    fail(p.what() + ": 'strategy_passes_max_depth' must be in 0.." + std::to_string(StrategyPasses::kMaxDepth) +
         " (bounces; the passes of longer paths are one 'rest' pass), got " +
         std::to_string(s.strategy_passes_max_depth));
  s.alpha.pass_alpha_threshold = p.get_float("pass_alpha_threshold", s.alpha.pass_alpha_threshold);
  if (!(s.alpha.pass_alpha_threshold >= 0 && s.alpha.pass_alpha_threshold <= 1))
    fail(p.what() + ": 'pass_alpha_threshold' must be in 0..1, got " + std::to_string(s.alpha.pass_alpha_threshold));
  s.seed = static_cast<uint32_t>(p.get_int("seed", 0));
  s.threads = p.get_int("threads", 0);
  if (s.threads < 0) fail(p.what() + ": 'threads' must not be negative");
  s.clamp = p.get_float("clamp", 0);
  if (s.clamp < 0) fail(p.what() + ": 'clamp' must not be negative");
  s.filter_width = clampf(p.get_float("filter_width", 1.5f), 0.01f, 10.0f);
  auto strategy = p.get_floats("strategy", 2, {-1, -1});
  s.strategy_s = clamped_int(strategy[0], -1, 1 << 20);
  s.strategy_t = clamped_int(strategy[1], -1, 1 << 20);
  if ((s.strategy_s >= 0) != (s.strategy_t >= 1) && !(s.strategy_s < 0 && s.strategy_t < 0))
    fail(p.what() + ": 'strategy' must be [s, t] with s >= 0 and t >= 1");
  s.strategy_unweighted = p.get_bool("strategy_unweighted", false);
  s.mis = p.get_string("mis", "power");
  if (s.mis != "power" && s.mis != "balance" && s.mis != "lafortune_willems")
    fail(p.what() + ": 'mis' must be power, balance or lafortune_willems, got '" + s.mis + "'");
  s.mlt_large_step = p.get_float("mlt_large_step", s.mlt_large_step);
  if (!(s.mlt_large_step >= 0 && s.mlt_large_step <= 1)) fail(p.what() + ": 'mlt_large_step' must be in 0..1");
  int bootstrap = p.get_int("mlt_bootstrap", int(s.mlt_bootstrap));
  if (bootstrap < 1 || bootstrap > 4096) fail(p.what() + ": 'mlt_bootstrap' must be in 1..4096 (samples per pixel)");
  s.mlt_bootstrap = uint32_t(bootstrap);
  int chains = p.get_int("mlt_chains", int(s.mlt_chains));
  if (chains < 1 || chains > 1 << 20) fail(p.what() + ": 'mlt_chains' must be in 1..1048576");
  s.mlt_chains = uint32_t(chains);
  s.mlt_step_size = p.get_float("mlt_step_size", s.mlt_step_size);
  if (!(s.mlt_step_size > 0 && s.mlt_step_size <= 1)) fail(p.what() + ": 'mlt_step_size' must be in (0, 1]");
  s.mlt_target = p.get_string("mlt_target", s.mlt_target);
  if (p.has("mlt_target") && s.mlt_target != "luminance" && s.mlt_target != "relative")
    fail(p.what() + ": 'mlt_target' must be luminance or relative, got '" + s.mlt_target + "'");
  if (const nlohmann::json *mutations = p.get_json("mlt_mutations")) {
    constexpr int kNames = mlt::kWeightedMutations;
    auto name = [](int i) { return mlt::mutation_name(mlt::MutationType(i + 1)); };
    std::string available;
    for (int i = 0; i < kNames; ++i) available += std::string(i ? ", " : "") + name(i);
    if (!mutations->is_object())
      fail(p.what() + ": 'mlt_mutations' must be an object of weights (" + available + ")");
    float sum = 0;
    for (int i = 0; i < kNames; ++i) s.mlt_mutations[i] = 0;
    for (auto it = mutations->begin(); it != mutations->end(); ++it) {
      int i = 0;
      while (i < kNames && it.key() != name(i)) ++i;
      if (i == kNames)
        fail(p.what() + ": 'mlt_mutations': unknown mutation '" + it.key() + "' (available: " + available + ")");
      const float w = it.value().is_number() ? it.value().get<float>() : -1.0f;
      if (!(w >= 0) || !std::isfinite(w)) fail(p.what() + ": 'mlt_mutations': '" + it.key() + "' must be a weight >= 0");
      s.mlt_mutations[i] = w;
      sum += w;
    }
    if (!(sum > 0)) fail(p.what() + ": 'mlt_mutations': the weights must not all be 0");
  }
  auto range = [&](const char *key, float (&out)[2], float hi, const char *what) {
    auto r = p.get_floats(key, 2, {out[0], out[1]});
    if (!(r[0] > 0 && r[0] < r[1] && r[1] <= hi))
      fail(p.what() + ": '" + key + "' must be [min, max] with 0 < min < max <= " + std::to_string(hi) + " (" + what + ")");
    out[0] = r[0];
    out[1] = r[1];
  };
  range("mlt_propagation_range", s.mlt_propagation_range, 10.0f, "fractions of the scene's bounding radius");
  range("mlt_scattering_angle", s.mlt_scattering_angle, kPi, "radians");
  range("mlt_caustic_angle", s.mlt_caustic_angle, kPi, "radians");
  s.mlt_keep_distances = p.get_float("mlt_keep_distances", s.mlt_keep_distances);
  if (!(s.mlt_keep_distances >= 0 && s.mlt_keep_distances <= 1))
    fail(p.what() + ": 'mlt_keep_distances' must be a probability in [0, 1]");
  s.mlt_equiangular = p.get_float("mlt_equiangular", s.mlt_equiangular);
  if (!(s.mlt_equiangular >= 0 && s.mlt_equiangular <= 1))
    fail(p.what() + ": 'mlt_equiangular' must be a probability in [0, 1]");
  const int direct = p.get_int("mlt_direct_samples", int(s.mlt_direct_samples));
  if (direct < 0 || direct > 65536)
    fail(p.what() + ": 'mlt_direct_samples' must be in 0..65536 (path-traced samples per pixel for direct light)");
  s.mlt_direct_samples = uint32_t(direct);
  if (const nlohmann::json *candidates = p.get_json("auto_candidates")) {
    s.auto_candidates.clear();
    if (!candidates->is_array() || candidates->empty())
      fail(p.what() + ": 'auto_candidates' must be a non-empty list of integrators");
    for (const nlohmann::json &c : *candidates) {
      const std::string name = c.is_string() ? c.get<std::string>() : c.dump();
      if (name != "path" && name != "bdpt" && name != "pssmlt" && name != "mmlt" && name != "mlt")
        fail(p.what() + ": 'auto_candidates': unknown integrator '" + name +
             "' (available: path, bdpt, pssmlt, mmlt, mlt)");
      s.auto_candidates.push_back(name);
    }
  }
  if (s.integrator == "auto") {
    if (!(s.time_limit > 0))
      fail(p.what() + ": integrator 'auto' picks by error x time: it needs a time limit ('time_limit')");
    if (s.sample_offset > 0)
      fail(p.what() + ": integrator 'auto' cannot render a part ('sample_offset'): every part must use one integrator");
    // Adaptive sampling is for path and bdpt: the pick is one of them.
    if (s.adaptive_sampling)
      s.auto_candidates.erase(std::remove_if(s.auto_candidates.begin(), s.auto_candidates.end(),
                                             [](const std::string &c) { return c != "path" && c != "bdpt"; }),
                              s.auto_candidates.end());
    if (s.auto_candidates.empty())
      fail(p.what() + ": integrator 'auto' with 'adaptive_sampling' needs path or bdpt among 'auto_candidates'");
    if (s.strategy_passes) {  // BDPT's own passes: the pick must be bdpt
      s.auto_candidates.erase(std::remove_if(s.auto_candidates.begin(), s.auto_candidates.end(),
                                             [](const std::string &c) { return c != "bdpt"; }),
                              s.auto_candidates.end());
      if (s.auto_candidates.empty())
        fail(p.what() + ": integrator 'auto' with 'strategy_passes' needs bdpt among 'auto_candidates'");
    }
  }
  s.border = {0, 0, s.width, s.height};
  auto b = p.get_floats("border", 4, {0, 0, float(s.width), float(s.height)});
  s.border = {clamped_int(b[0], 0, s.width), clamped_int(b[1], 0, s.height), clamped_int(b[2], 0, s.width),
              clamped_int(b[3], 0, s.height)};
  if (s.border.width() <= 0 || s.border.height() <= 0) fail(p.what() + ": 'border' is empty");
  p.check_all_used();
  if (s.adaptive_sampling && s.integrator != "path" && s.integrator != "bdpt" && s.integrator != "auto")
    fail(p.what() + ": 'adaptive_sampling' is for path and bdpt; " + s.integrator +
         " spreads its mutations by brightness itself");
  if (s.adaptive_sampling && s.sample_offset > 0)
    fail(p.what() + ": 'adaptive_sampling' cannot render a part ('sample_offset' " + std::to_string(s.sample_offset) +
         "): each pixel's sample count depends on the samples before it, so parts would not add up");
  if (s.strategy_passes && s.integrator != "bdpt" && s.integrator != "auto")
    fail(p.what() + ": 'strategy_passes' are bidirectional path tracing's strategies (s, t); " + s.integrator +
         " has none of them (render the passes with bdpt)");
  // Before the session allocates anything: the film, and Metropolis' bootstrap and chains.
  std::string film = std::to_string(s.width) + "x" + std::to_string(s.height) + " film";
  double bytes = double(s.width) * double(s.height) *
                 double(Film::bytes_per_pixel(s.estimates_noise(), s.light_passes, s.strategy_pass_depth(),
                                                s.denoising_passes, s.shader_aovs.channels,
                                                s.cryptomatte.slots_per_pixel()));
  if (s.integrator == "pssmlt" || s.integrator == "mmlt" || s.integrator == "mlt") {
    bytes += mlt::Metropolis::memory_estimate(s, s.integrator == "mmlt", s.integrator == "mlt");
    film += " with " + s.integrator + "'s bootstrap (" + std::to_string(s.mlt_bootstrap) + " per pixel) and " +
            std::to_string(s.mlt_chains) + " chains";
  }
  if (s.integrator == "auto") {  // a pilot's film next to the render's, and the largest candidate
    bytes *= 2;
    double largest = 0;
    for (const std::string &c : s.auto_candidates)
      if (c == "pssmlt" || c == "mmlt") largest = std::max(largest, mlt::Metropolis::memory_estimate(s, c == "mmlt"));
    bytes += largest;
    film += " with integrator auto's pilot film and candidates";
  }
  check_memory(p.what(), film, bytes);
  return s;
}

std::string RenderSettings::image_settings_json() const {
  nlohmann::json j;
  j["width"] = width;
  j["height"] = height;
  j["integrator"] = integrator;
  j["sampler"] = sampler;
  j["max_bounces"] = max_bounces;
  j["seed"] = seed;
  j["clamp"] = clamp;
  if (limits.classify || limits.clamps) {  // written only when used: older parts stay comparable
    auto bounces = [](int n) { return n >= LightPathLimits::kNoLimit ? -1 : n; };
    j["diffuse_bounces"] = bounces(limits.diffuse);
    j["glossy_bounces"] = bounces(limits.glossy);
    j["transmission_bounces"] = bounces(limits.transmission);
    j["volume_bounces"] = bounces(limits.volume);
    j["caustics_reflective"] = limits.caustics_reflective;
    j["caustics_refractive"] = limits.caustics_refractive;
    j["clamp_direct"] = limits.clamp_direct;
    j["clamp_indirect"] = limits.clamp_indirect;
  }
  if (limits.filter_glossy > 0) j["filter_glossy"] = limits.filter_glossy;  // (older parts: off)
  if (limits.transparent < LightPathLimits::kNoLimit) j["transparent_max_bounces"] = limits.transparent;  // (older: none)
  if (alpha.pass_alpha_threshold != FilmAlpha{}.pass_alpha_threshold)  // the index passes' (older parts: default)
    j["pass_alpha_threshold"] = alpha.pass_alpha_threshold;
  if (alpha.film_transparent) {  // written only when used: older parts stay comparable
    j["film_transparent"] = true;
    j["film_transparent_glass"] = alpha.transparent_glass;
    j["film_transparent_roughness"] = alpha.glass_roughness;
  }
  j["filter_width"] = filter_width;
  j["border"] = {border.x0, border.y0, border.x1, border.y1};
  j["strategy"] = {strategy_s, strategy_t};
  j["strategy_unweighted"] = strategy_unweighted;
  j["mis"] = mis;
  // Path and BDPT draw their samples from two replicates when they estimate the noise.
  if (estimates_noise()) j["noise_estimate"] = true;
  if (adaptive_sampling) {
    j["adaptive_threshold"] = adaptive_threshold;
    j["adaptive_min_samples"] = adaptive_first_check();
  }
  if (integrator == "pssmlt" || integrator == "mmlt" || integrator == "mlt") {
    j["mlt_large_step"] = mlt_large_step;
    j["mlt_bootstrap"] = mlt_bootstrap;
    j["mlt_chains"] = mlt_chains;
    j["mlt_step_size"] = mlt_step_size;
    j["mlt_target"] = relative_mlt_target(integrator == "mlt") ? "relative" : "luminance";
    if (integrator == "mlt") {
      nlohmann::json weights = nlohmann::json::object();
      for (int i = 0; i < mlt::kWeightedMutations; ++i)
        weights[mlt::mutation_name(mlt::MutationType(i + 1))] = mlt_mutations[i];
      j["mlt_mutations"] = weights;
      j["mlt_propagation_range"] = {mlt_propagation_range[0], mlt_propagation_range[1]};
      j["mlt_scattering_angle"] = {mlt_scattering_angle[0], mlt_scattering_angle[1]};
      j["mlt_caustic_angle"] = {mlt_caustic_angle[0], mlt_caustic_angle[1]};
      j["mlt_keep_distances"] = mlt_keep_distances;
      j["mlt_equiangular"] = mlt_equiangular;
      j["mlt_direct_samples"] = mlt_direct_samples;
    }
  }
  return j.dump();
}

}  // namespace rdv
