// Metropolis light transport over BDPT's primary sample space:
//  - Kelemen et al. 2002 ("pssmlt"): a state is the vector of uniform numbers one BDPT
//    sample consumes; its target is the luminance of that sample's whole MIS-weighted
//    estimate (the camera sample and every light-tracing splat);
//  - Hachisuka et al. 2014, multiplexed ("mmlt"): a state also picks a path depth and one
//    (s, t) strategy, and its target is that strategy's MIS-weighted contribution.
// A bootstrap of independent samples estimates the normalisation b and picks each
// chain's start by importance; a fixed number of chains, each seeded by (seed, chain)
// (a farm part by (seed, sample_offset, chain): an independent chain set, docs/farm.md),
// run in parallel and their splats (Veach's expected values of proposal and state;
// the image is b / mutations times their sum, b refined by every large step) are applied
// in chain order after each pass, so the image is the same on any
// number of threads. `samples` counts mutations per pixel.
#pragma once
#include <memory>
#include <mutex>
#include <string>
#include <vector>
#include "integrators/bdpt/bdpt.h"
#include "integrators/mlt/importance_map.h"
#include "integrators/mlt/path_space.h"
#include "integrators/path/path_tracer.h"
#include "samplers/pss_sampler.h"

namespace rdv::mlt {

struct MltSettings {
  bool multiplexed = false;
  // Veach's path-space MLT ("mlt", path_space.h): states are explicit paths, mutated by
  // the bidirectional mutation; large steps regenerate the whole path. Luminance target.
  bool path_space = false;
  MutationSettings mutations;  // mlt
  float large_step_probability = 0.3f;
  uint32_t bootstrap_per_pixel = 1;  // bootstrap samples per pixel of the rendered region (at least 4096)
  uint32_t chains = 256;
  float step_size = 0.01f;  // standard deviation of a small step, in primary sample space
  // The chains' target: false, the luminance of a state's splats (Kelemen, Hachisuka);
  // true, their luminance relative to a pilot's coarse image there (importance_map.h).
  bool relative_target = true;
  // mlt: camera samples per pixel of the path tracer for the paths of one and two edges
  // (a light seen directly, direct lighting), which the chains then leave out (Veach 1997,
  // ch. 11: direct lighting by standard methods); 0: the chains take every path. Needs
  // max_bounces >= 2 (else every path is direct and the chains take them all).
  uint32_t direct_samples = 0;
};

// A state of a chain: where its sample lands on the image (in units where one sample's
// splats estimate the whole image) and the scalar the chain targets.
struct State {
  std::vector<Splat> splats;
  // Light passes (the film keeps them; light_passes.cpp): the slot shares of the splats
  // that carry some (Splat::light_pass.shares), in splat order.
  std::vector<SlotShare> shares;
  float target = 0;
  // An independent sample of b when the state was sampled independently (a large step
  // or the bootstrap): the target itself in primary sample space, target / q in path space.
  double independent = 0;
  int depth = -1, s = -1;  // multiplexed: the strategy of the state
};

// What the chains did (read by stats_json while rendering).
struct MltStats {
  uint64_t bootstrap_samples = 0, mutations = 0;
  uint64_t small_steps = 0, small_accepted = 0, large_steps = 0, large_accepted = 0;
  uint64_t large_found = 0;  // large-step proposals that carry light (target > 0)
  double b = 0, b_standard_error = 0;
  uint64_t pilot_samples = 0;  // relative target: the pilot's independent samples
  float relative_share = 0;  // relative target: share of the map's blocks brighter than the mean
  std::vector<double> depth_b;  // multiplexed: b of each path depth
  // multiplexed: b of each (depth, s) strategy, from the bootstrap's independent samples
  // (the target distribution the chains' strategy_counts follow)
  std::vector<double> strategy_b;
  // multiplexed: how many mutations ended in each (depth, s) state, depth-major
  // (depth d has d + 2 strategies, depth 0 one).
  std::vector<uint64_t> strategy_counts;
  uint64_t type_proposed[kMutationTypes] = {}, type_accepted[kMutationTypes] = {};  // path space
  std::string warning;
};

class Metropolis final : public Integrator {
 public:
  Metropolis(const Scene &scene, const RenderSettings &settings, const bdpt::BdptSettings &bdpt_settings,
             const MltSettings &mlt);
  void render(RenderContext &ctx) override;
  std::string stats_json() const override;
  // Bytes the bootstrap (its targets and their distribution) and the chains will take:
  // checked against the memory budget before a session is made.
  static double memory_estimate(const RenderSettings &settings, bool multiplexed, bool path_space = false);

  // One state from the sampler's numbers (contribution.cpp). depth_override >= 0
  // (multiplexed bootstrap): that depth instead of the one the numbers pick.
  void evaluate(PssSampler &sampler, RayStats &stats, State &state, int depth_override = -1) const;
  // Index of the (depth, s) state in MltStats::strategy_counts.
  // Depth 0 has one strategy (s = 0), depth d >= 1 has d + 2.
  static size_t strategy_index(int depth, int s) {
    return depth == 0 ? 0 : 1 + size_t(depth - 1) * (depth + 4) / 2 + size_t(s);
  }

 private:
  // Path space: the state of an evaluated explicit path (its one splat).
  void path_state(const ExplicitPath &path, State &state) const;
  // Path space: the chains' target for a path (its luminance, over the pilot's image there
  // with the relative target).
  float path_target(const ExplicitPath &path) const;
  // Cycles' light passes (light_passes.cpp, film/light_passes.h): splat i of the state
  // (a camera sample) gets the slots of `passes` times scale as its shares; a path-space
  // state's splat is classified by the path's first scattering vertex from the camera.
  static void add_shares(State &state, size_t i, const LightPassSample &passes, float scale);
  static void classify_path(const ExplicitPath &path, State &state);
  const char *name() const { return mlt_.path_space ? "mlt" : mlt_.multiplexed ? "mmlt" : "pssmlt"; }
  void evaluate_kelemen(PssSampler &sampler, RayStats &stats, State &state) const;
  template <bool kMedia>
  void evaluate_multiplexed(PssSampler &sampler, RayStats &stats, State &state, int depth_override) const;
  CameraRay camera_sample(Sampler &sampler, Vec2 *raster) const;
  // The scalar a chain follows for a state's splats (luminance, or relative luminance).
  // With a shadow catcher, Combined's and the catcher pass's splats: each sum the film
  // keeps is then estimated without bias (the matte's are a part of Combined's).
  float target_of(const std::vector<Splat> &splats) const;
  // Relative target: the coarse image from independent samples that the target divides by.
  ImportanceMap pilot(RenderContext &ctx, int depths);
  // Depth, normal, albedo, alpha, the data passes and the light passes' colours from a few
  // camera rays per pixel (MLT has no per-pixel samples).
  void first_hit_pass(RenderContext &ctx) const;
  // Direct light left to the path tracer (MltSettings::direct_samples): its camera samples
  // fill the pixel sums (Combined is their mean plus the chains' splats) and, in place of
  // the first-hit pass, the AOVs, alpha, data and colour passes.
  void direct_pass(RenderContext &ctx) const;

  const Scene &scene_;
  RenderSettings settings_;
  bdpt::Bdpt bdpt_;
  MltSettings mlt_;
  // Camera samples fall uniformly on the rendered region grown by the filter radius (so
  // edge pixels see their whole filter); its area in pixels makes a camera sample's
  // estimate of the image.
  Vec2 sample_origin_, sample_size_;
  float region_area_;
  float image_area_;      // light-tracing splats carry the camera importance of the whole image
  Distribution1D depth_distribution_;  // multiplexed: path depth by b
  ImportanceMap importance_;  // empty: the luminance target
  bool light_passes_ = false;  // the film keeps Cycles' light passes: states carry their split
  // A scene with a shadow catcher whose sums the film keeps: states carry the matte and
  // catcher pass (contribution.cpp; mlt: each path's f_catcher), the first-hit pass their
  // camera side.
  bool catchers_ = false;
  std::unique_ptr<PathSpace> path_space_;  // mlt only
  std::unique_ptr<PathTracer> direct_;     // mlt with direct_samples: paths of one and two edges

  mutable std::mutex stats_mutex_;
  MltStats stats_;
};

}  // namespace rdv::mlt
