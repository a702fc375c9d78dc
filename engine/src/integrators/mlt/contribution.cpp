// What a Metropolis state contributes: the path(s) its primary sample vector makes,
// as splats on the image, and the scalar the chain targets (their luminance).
// A state's splats estimate the whole image: a camera sample falls uniformly on the
// sample region (density 1 / region_area_) and light-tracing splats carry the camera's
// importance normalised over the whole image, so E[splats to pixel j] = I_j.
#include "integrators/mlt/metropolis.h"
#include "integrators/bdpt/pass_class.h"
#include "samplers/dimension_layout.h"

namespace rdv::mlt {

CameraRay Metropolis::camera_sample(Sampler &sampler, Vec2 *raster) const {
  sampler.start_sample(0, 0, 0);
  Vec2 u = sampler.get_2d();
  *raster = {sample_origin_.x + u.x * sample_size_.x, sample_origin_.y + u.y * sample_size_.y};
  CameraRay cr;
  cr.ray = scene_.camera_now().generate_ray(*raster, sampler.get_2d(), &cr.lens_point, &cr.cone);
  return cr;
}

float Metropolis::target_of(const std::vector<Splat> &splats) const {
  double sum = 0;
  if (importance_.empty()) {
    for (const Splat &sp : splats)
      if (sp.catcher != CatcherSplat::Matte) sum += luminance(sp.L);
  } else {
    for (const Splat &sp : splats)
      if (sp.catcher != CatcherSplat::Matte) sum += double(luminance(sp.L)) * importance_.weight(sp.raster);
  }
  return float(sum);
}

void Metropolis::evaluate_kelemen(PssSampler &sampler, RayStats &stats, State &state) const {
  Vec2 raster;
  CameraRay cr = camera_sample(sampler, &raster);
  size_t first_light_splat = state.splats.size();
  state.splats.push_back({raster, Color(0.0f), Splat::kNoStrategy, {}, CatcherSplat::Combined});
  // Light passes: BDPT splits the camera sample by slot (its light-tracing splats carry
  // their own split); the colour passes and the AOVs come from the first-hit pass.
  LightPassSample passes;
  FirstHit first_hit;
  first_hit.aovs = false;
  if (light_passes_) {
    passes.clear();
    first_hit.passes = &passes;
  }
  // Shadow catchers: BDPT's sample makes its matte and its copy's catcher pass too, and
  // tags its light-tracing splats (CatcherSplat).
  CatcherSample catcher;
  if (catchers_) first_hit.catcher = &catcher;
  Color L = bdpt_.Li(cr, sampler, stats, light_passes_ || catchers_ ? &first_hit : nullptr, state.splats);
  // Never NaN / Inf or a negative value into the film or the acceptance ratio.
  const bool valid = is_finite(L) && L.x >= 0 && L.y >= 0 && L.z >= 0 && (!catchers_ || catcher.valid());
  // The sample clamp caps the camera sample as BDPT's tile loop does (its light-tracing
  // splats are not capped there either): the chains then target BDPT's clamped image.
  const float clamp = settings_.clamp;
  if (valid && clamp > 0 && max_component(L) > clamp) {
    const float scale = clamp / max_component(L);
    L *= scale;
    if (light_passes_) passes.scale(scale);
    catcher.matte *= scale;  // a part of L: scaled with it
  }
  state.splats[first_light_splat].L = valid ? L * region_area_ : Color(0.0f);
  if (valid && light_passes_) add_shares(state, first_light_splat, passes, region_area_);
  for (size_t i = first_light_splat + 1; i < state.splats.size(); ++i) state.splats[i].L *= image_area_;
  if (valid && catchers_) {
    // The camera sample's matte and catcher pass as splats of their own where its Combined
    // lands (film/shadow_catcher_passes.h; the first-hit pass adds the camera side; the
    // pass's splat counts the split). The pass is clamped as a Combined of its own, as
    // BDPT's tile loop does.
    if (clamp > 0 && max_component(catcher.catcher) > clamp) catcher.catcher *= clamp / max_component(catcher.catcher);
    state.splats.push_back({raster, catcher.matte * region_area_, Splat::kNoStrategy, {}, CatcherSplat::Matte});
    state.splats.push_back({raster, catcher.catcher * region_area_, Splat::kNoStrategy, {}, CatcherSplat::SplitPass});
  }
}

template <bool kMedia>
void Metropolis::evaluate_multiplexed(PssSampler &sampler, RayStats &stats, State &state, int depth_override) const {
  // The strategy: a path depth by its share of b (changed by large steps only) and one
  // of its strategies, uniformly.
  sampler.start_stream(SampleStream::Strategy, 0);
  float u_depth = sampler.get_1d();
  float u_strategy = sampler.get_1d();
  float depth_pmf = 1;
  int depth = depth_override;
  if (depth < 0) depth = int(depth_distribution_.sample_discrete(u_depth, &depth_pmf));
  const int strategies = depth == 0 ? 1 : depth + 2;
  const int s = depth == 0 ? 0 : std::min(int(u_strategy * strategies), strategies - 1);
  const int t = depth + 2 - s;
  state.depth = depth;
  state.s = s;

  thread_local std::vector<bdpt::PathVertex> camera_path, light_path;
  thread_local std::vector<Color> emitted;
  const size_t capacity = size_t(bdpt_.settings().max_bounces) + 2;
  if (camera_path.size() < capacity) { camera_path.resize(capacity); light_path.resize(capacity); }
  emitted.assign(capacity, Color(0.0f));
  Vec2 raster;
  CameraRay cr = camera_sample(sampler, &raster);
  const int nc = bdpt_.camera_subpath<kMedia>(cr, sampler, stats, camera_path.data(), emitted.data(), t);
  Vec2 light_raster;
  Color c(0.0f);
  // Light passes: the strategy's path classified as BDPT classifies it.
  const bool light_passes = light_passes_;
  LightPassSample passes;
  bdpt::Bdpt::PassClass pc;
  Vec3 connection_dir(0.0f);
  if (s == 0) {
    // The camera path ends at an emitter hit (vertex t - 1), or at a lamp or emissive
    // medium its last segment passed (BDPT weighs those on the walk).
    c = emitted[size_t(t - 2)];
    Color hit(0.0f);
    if (nc == t) {
      hit = bdpt_.connect<kMedia>(light_path.data(), camera_path.data(), 0, t, sampler, stats, &light_raster, nullptr);
      c += hit;
    }
    if (light_passes) {
      passes.clear();
      pc = bdpt_.pass_class(light_path.data(), camera_path.data(), 0, t, connection_dir, {});
      passes.add(emitted[size_t(t - 2)], pc.scatterings, pc.first);
      if (nc == t) bdpt_.add_light_pass(camera_path.data(), 0, t, pc, hit, passes);
    }
  } else if (nc == t &&  // s = 1 samples a light point of its own (next-event estimation): no light subpath
             (s < 2 || bdpt_.light_subpath<kMedia>(sampler, stats, light_path.data(), s) == s)) {
    c = bdpt_.connect<kMedia>(light_path.data(), camera_path.data(), s, t, sampler, stats, &light_raster, nullptr,
                              light_passes ? &connection_dir : nullptr);
    if (light_passes) {
      passes.clear();
      pc = bdpt_.pass_class(light_path.data(), camera_path.data(), s, t, connection_dir, {});
      if (t >= 2) bdpt_.add_light_pass(camera_path.data(), s, t, pc, c, passes);
    }
  }
  // One strategy of `strategies`, at a depth chosen with probability depth_pmf.
  const float per_strategy = float(strategies) / depth_pmf;
  // Shadow catchers: the strategy's path sorted by the split as BDPT's sample loop sorts
  // it (the matte's unless past the split; no light passes past it), then the same
  // strategy of the sample's copy (the storage is free again), which may carry light where
  // the main path carries none: the target counts both.
  const int split = catchers_ ? bdpt_.split_vertex(camera_path.data(), nc) : -1;
  auto past_split = [split](int vertex) { return split >= 0 && vertex >= split; };
  const bool caught = catchers_ && (t == 1 ? light_path[size_t(s - 1)].catcher : past_split(t - 1));
  // s = 0 split at its last vertex: the lamp it passed before is the matte's (a splat of its own).
  const Color passed_matte = catchers_ && s == 0 && caught && !past_split(t - 2) ? emitted[size_t(t - 2)] : Color(0.0f);
  const CatcherSplat tag = catchers_ && !caught ? CatcherSplat::CombinedAndMatte : CatcherSplat::Combined;
  if (is_finite(c) && !is_black(c) && c.x >= 0 && c.y >= 0 && c.z >= 0) {
    c *= per_strategy;
    if (t == 1) {
      state.splats.push_back({light_raster, c * image_area_, Splat::kNoStrategy,
                              {pc.first, light_passes && !caught, pc.scatterings > 1}, tag});
    } else {
      state.splats.push_back({raster, c * region_area_, Splat::kNoStrategy, {}, tag});
      if (light_passes && !caught) add_shares(state, state.splats.size() - 1, passes, per_strategy * region_area_);
      if (!is_black(passed_matte))
        state.splats.push_back({raster, passed_matte * (per_strategy * region_area_), Splat::kNoStrategy, {},
                                CatcherSplat::Matte});
    }
  }
  if (!catchers_) return;
  Vec2 copy_raster;
  Color copy = bdpt_.catcher_strategy<kMedia>(cr, sampler, stats, s, t, split, camera_path.data(), light_path.data(),
                                              emitted.data(), capacity, &copy_raster);
  if (!is_finite(copy) || is_black(copy) || copy.x < 0 || copy.y < 0 || copy.z < 0) return;
  copy *= per_strategy;
  // A camera sample's copy counts its split where it lands (CatcherSplat::SplitPass).
  state.splats.push_back({t == 1 ? copy_raster : raster, copy * (t == 1 ? image_area_ : region_area_),
                          Splat::kNoStrategy, {}, t == 1 ? CatcherSplat::Pass : CatcherSplat::SplitPass});
}

void Metropolis::evaluate(PssSampler &sampler, RayStats &stats, State &state, int depth_override) const {
  state.splats.clear();
  state.shares.clear();
  state.depth = state.s = -1;
  const bool media = scene_.has_media();
  // Motion blur: the state's shutter time is one more primary sample (the Camera stream's
  // kCameraTime), mutated as the others; the whole state is traced at it.
  shutter::SampleTime at(scene_.has_motion() ? dims::shutter_time(sampler) : shutter::now());
  if (!mlt_.multiplexed) evaluate_kelemen(sampler, stats, state);  // Li decides on media itself
  else if (media) evaluate_multiplexed<true>(sampler, stats, state, depth_override);
  else evaluate_multiplexed<false>(sampler, stats, state, depth_override);
  state.target = target_of(state.splats);
  if (!std::isfinite(state.target)) {  // an overflow in a splat: the state carries nothing
    state.splats.clear();
    state.shares.clear();
    state.target = 0;
  }
  state.independent = state.target;
}

void Metropolis::path_state(const ExplicitPath &path, State &state) const {
  state.splats.clear();
  state.shares.clear();
  state.depth = state.s = -1;
  state.independent = 0;
  state.target = path_target(path);
  if (state.target > 0 && std::isfinite(state.target)) {
    // Shadow catchers: a path past its split adds to Combined only, and to no light pass (as
    // after BDPT's split); one that does not split, to the matte too. A split path's
    // f_catcher goes to the catcher pass with the same weight (path_space.h).
    const bool split = catchers_ && path.split >= 0;
    state.splats.push_back({path.raster, path.f, Splat::kNoStrategy, {},
                            catchers_ && !split ? CatcherSplat::CombinedAndMatte : CatcherSplat::Combined});
    if (light_passes_ && !split) classify_path(path, state);
    if (split) state.splats.push_back({path.raster, path.f_catcher, Splat::kNoStrategy, {}, CatcherSplat::SplitPass});
  } else {
    state.target = 0;
  }
}

float Metropolis::path_target(const ExplicitPath &path) const {
  const float y = path.carried();
  return importance_.empty() || !(y > 0) ? y : y * importance_.weight(path.raster);
}

}  // namespace rdv::mlt
