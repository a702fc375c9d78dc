// What every integrator shares: the render settings, the first-hit AOV record, ray
// statistics, the render context a session hands over, and the registry that builds
// one by name.
#pragma once
#include <tbb/task_arena.h>
#include <memory>
#include <string>
#include <vector>
#include "core/hash.h"
#include "core/params.h"
#include "film/film.h"
#include "film/pixel_filter.h"
#include "integrators/film_alpha.h"
#include "integrators/light_path_limits.h"
#include "render/render_control.h"
#include "samplers/sampler.h"
#include "scene/scene.h"

namespace rdv {

struct RenderSettings {
  int width = 640, height = 480;
  std::string integrator = "path";
  // Integrator "auto": the integrators its pilots compare (integrators/auto/). mlt is one
  // since the study measured it (docs/trade.md: lowest on the four scenes of light through a
  // gap); a scene it refuses leaves it out.
  std::vector<std::string> auto_candidates = {"path", "bdpt", "pssmlt", "mmlt", "mlt"};
  std::string sampler = "sobol";  // or "independent"
  uint32_t samples = 128;  // 0 = no sample limit (then time_limit > 0)
  // A part of a render (farm task): samples [sample_offset, sample_offset + samples) of
  // the sequence (path, bdpt); Metropolis: the chain set of task sample_offset
  // (seed_for_chains). docs/farm.md.
  uint32_t sample_offset = 0;
  // Whatever the caller identifies the scene by (the CLI: a hash of the scene file);
  // written into render parts so that parts of different scenes are never merged.
  std::string scene_hash;
  double time_limit = 0;   // seconds, 0 = off
  // Halt once the estimated relative MSE of the image falls below this (0 = off;
  // film/noise_estimate.h, docs/noise.md).
  double noise_target = 0;
  // Estimate the noise (and fill the Noise pass) even without a noise target.
  bool noise_pass = false;
  // Adaptive sampling (path, bdpt; Cycles' Noise Threshold): a pixel whose estimated
  // relative error, over its 3 x 3 neighbourhood, is at most adaptive_threshold after
  // at least adaptive_min_samples (0: kAutoAdaptiveMinSamples) gets no more samples.
  bool adaptive_sampling = false;
  float adaptive_threshold = 0.01f;
  uint32_t adaptive_min_samples = 0;
  static constexpr uint32_t kAutoAdaptiveMinSamples = 16;
  uint32_t adaptive_first_check() const {
    return adaptive_min_samples ? adaptive_min_samples : kAutoAdaptiveMinSamples;
  }
  int max_bounces = 12;
  uint32_t seed = 0;
  int threads = 0;         // 0 = all cores
  float clamp = 0;         // 0 = off
  // Cycles' Light Paths: per-kind bounce limits, caustics switches, direct / indirect
  // clamps (integrators/light_path_limits.h); all off by default.
  LightPathLimits limits;
  // Cycles' light passes (film/light_passes.h): the film keeps them (every integrator).
  bool light_passes = false;
  // BDPT's strategy passes (film/strategy_passes.h) of paths up to max depth (bounces).
  bool strategy_passes = false;
  int strategy_passes_max_depth = 3;
  int strategy_pass_depth() const { return strategy_passes ? strategy_passes_max_depth : -1; }
  // Mist, Object Index and Material Index (film/data_passes.h) as EXR layers; the film
  // has them either way (every integrator), for reads.
  bool data_passes = false;
  // Cycles' denoising data (film/denoising_passes.h): the film keeps them (every integrator).
  bool denoising_passes = false;
  // Shader AOVs (film/shader_aovs.h, setting "aovs"): the film keeps them (every integrator).
  ShaderAovs shader_aovs;
  // Cryptomatte (film/cryptomatte.h, setting "cryptomatte"): the film keeps it (every integrator).
  Cryptomatte cryptomatte;
  // View Layer > Passes > Shadow Catcher (film/shadow_catcher_passes.h): in a scene with a
  // shadow catcher Combined reads as the matte (else with the shadow in it, as Cycles'
  // approximate shadow catcher).
  bool shadow_catcher_pass = false;
  // Film > Transparent and holdouts (integrators/film_alpha.h); holdouts is the scene's.
  FilmAlpha alpha;
  float filter_width = 1.5f;
  Rect border;             // the rendered region
  // BDPT debug view: only the (s, t) strategy contributes, MIS-weighted unless unweighted.
  int strategy_s = -1, strategy_t = -1;
  bool strategy_unweighted = false;
  // BDPT: how strategies share a path: "power" (Veach's power heuristic), "balance" or
  // "lafortune_willems" (the original paper's specularity-based weights).
  std::string mis = "power";
  // Metropolis (pssmlt, mmlt): probability of a large step, bootstrap samples per pixel,
  // number of chains, small-step size (standard deviation in primary sample space).
  float mlt_large_step = 0.3f;
  uint32_t mlt_bootstrap = 1;
  uint32_t mlt_chains = 256;
  float mlt_step_size = 0.01f;
  // What the chains follow: "luminance" or "relative" (luminance over a pilot's coarse image).
  // "" (not given): each integrator's own, relative for pssmlt and mmlt, luminance for mlt
  // (Veach's: the relative target's runs spread wider there, docs/mlt.md).
  std::string mlt_target;
  // mlt (path space): weights of the mutations that are not large steps (bidirectional,
  // lens, propagation, scattering perturbation; Pauly et al. 2000; caustic and multi-chain
  // perturbations, lens subpath mutation, Veach 1997), the propagation distance range
  // [min, max] in fractions of the scene's bounding radius and the scattering and caustic
  // (also multi-chain) angle ranges in radians (all drawn with density ~ 1 / x).
  float mlt_mutations[7] = {1.0f, 1.0f, 1.0f, 1.0f, 1.0f, 1.0f, 1.0f};
  float mlt_propagation_range[2] = {1e-4f, 0.1f};
  float mlt_scattering_angle[2] = {1e-4f, 0.2f};
  float mlt_caustic_angle[2] = {1e-4f, 0.05f};
  // mlt in scenes with media: the probability that a lens, caustic or multi-chain
  // perturbation retraces as Pauly et al.'s do, keeping each medium vertex's distance.
  float mlt_keep_distances = 0.5f;
  // mlt in scenes with scattering media and point or spot lamps: the probability that a
  // camera-side walk draws a distance in a medium equiangularly toward a lamp (Kulla and
  // Fajardo) instead of by free flight (mlt/equiangular.h; 0: free flights only).
  float mlt_equiangular = 0.0f;
  // mlt: path-traced camera samples per pixel for direct light (paths of one and two
  // edges), which the chains then leave out (0: the chains take every path).
  uint32_t mlt_direct_samples = 0;

  static RenderSettings from_params(Params &p);
  // Whether a Metropolis integrator's chains follow the relative target: mlt_target's value,
  // or when not given each integrator's own (relative; path space, mlt: luminance).
  bool relative_mlt_target(bool path_space) const {
    return path_space ? mlt_target == "relative" : mlt_target != "luminance";
  }
  // Whether the render estimates its noise: half images from independent replicates
  // (path, bdpt; a different image than without), and the frame's estimate after each
  // pass (O(pixels)).
  bool estimates_noise() const { return noise_target > 0 || noise_pass || adaptive_sampling; }
  // Seed of the Metropolis bootstrap and chains: the seed itself for the first part
  // (sample_offset 0, so a whole render is unchanged), an independent one per part.
  uint32_t seed_for_chains() const { return sample_offset == 0 ? seed : hash_combine(seed, sample_offset); }
  // Every setting that changes the image except the sample range, the halt and the
  // thread count (parts of one render must agree on it), as a JSON object text.
  std::string image_settings_json() const;
};

struct RayStats {
  uint64_t rays = 0;
};

struct FirstHit {
  bool valid = false;
  float depth = 1e10f;
  Vec3 normal{0.0f};
  Color albedo{0.0f};
  // What of the sample sees the transparent background or a holdout (film_alpha.h):
  // the pixel's alpha is 1 minus its mean.
  float transparency = 0;
  // Mist, Object Index and Material Index (film/data_passes.h), along the camera's
  // see-through chain.
  DataPassSample data;
  // Cycles' light passes of the sample, when the film keeps them (else null): the
  // integrator adds each contribution's share (film/light_passes.h); its splats carry
  // their own (Splat::light_pass).
  LightPassSample *passes = nullptr;
  // The sample's shadow catcher values when the film keeps them (the path tracer and BDPT
  // in a scene with a catcher, and BDPT's samples in pssmlt; film/shadow_catcher_passes.h),
  // else null.
  CatcherSample *catcher = nullptr;
  // BDPT's strategy passes of the sample, when the film keeps them (else null): each
  // strategy's contribution goes to strategies[layout.index(s, t)], a t = 1 strategy's
  // splat carries that index (Splat::strategy; film/strategy_passes.h).
  StrategyPasses strategy_layout;
  Color *strategies = nullptr;
  // false: the caller keeps only `passes`' light slots and `strategies` (the Metropolis
  // integrators, whose AOVs, data passes, alpha and colour passes come from a first-hit
  // pass of their own), so the integrator computes none of the rest and leaves the
  // other fields as they are.
  bool aovs = true;
};

// A contribution to wherever on the image a light path reaches the camera.
// strategy: its BDPT strategy pass (film/strategy_passes.h), kNoStrategy for none.
// light_pass: its light passes (film/light_passes.h) when the film keeps them: the split of
// its path's first scattering vertex, and whether that was not the only one.
// catcher: in a scene with a shadow catcher, the sums it adds to (film/shadow_catcher_passes.h).
struct Splat {
  static constexpr uint8_t kNoStrategy = 0xff;
  Vec2 raster;
  Color L;
  uint8_t strategy = kNoStrategy;
  SplatLightPass light_pass;
  CatcherSplat catcher = CatcherSplat::Combined;
};

struct CameraRay {
  Ray ray;          // starts at the near clip plane
  Vec3 lens_point;  // where on the lens it comes from (BDPT's camera vertex)
  RayCone cone;     // its footprint, for filtered texture lookups
};

// What a session hands the integrator that renders for it (pbrt-v4's Integrator::Render
// idea: the session schedules, halts and publishes; the integrator renders).
struct RenderContext {
  const Scene &scene;
  const RenderSettings &settings;
  Film &film;                  // the frame: pixel samples, splats (and their scale), AOVs
  const PixelFilter &filter;
  RenderControl &control;      // when to stop; where progress goes
  tbb::task_arena &arena;      // the session's threads
};

class Integrator {
 public:
  virtual ~Integrator() = default;
  // Renders into ctx.film until the settings' sample count is reached or
  // ctx.control.should_stop(), publishing progress (and, for splats, their scale)
  // after each complete pass, with its half images, and reporting the frame's noise
  // estimate when the settings ask for one (estimates_noise()); stops within ~100 ms of
  // a cancel.
  virtual void render(RenderContext &ctx) = 0;
  // Figures of the integrator's own (MLT: acceptance, chains, normalisation), as a JSON
  // object; readable from any thread while rendering.
  virtual std::string stats_json() const { return "{}"; }
};

// The registry: one line per integrator.
std::unique_ptr<Integrator> make_integrator(const RenderSettings &settings, const Scene &scene);

}  // namespace rdv
