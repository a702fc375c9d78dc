// BDPT's camera sample (Bdpt::li), as a template: bdpt.cpp compiles it for scenes without a
// shadow catcher, shadow_catcher.cpp for scenes with one, each in its own translation unit
// so that neither changes how the compiler inlines the other (the loop without catchers is
// the one every other scene runs).
#pragma once
#include "integrators/bdpt/bdpt.h"
#include "integrators/bdpt/pass_class.h"

namespace rdv::bdpt {

template <bool kMedia, bool kCatcher>
Color Bdpt::li(const CameraRay &camera_ray, Sampler &sampler, RayStats &stats, FirstHit *first_hit,
               std::vector<Splat> &splats) const {
  // Subpath storage reused across samples: no allocation in the sample loop.
  thread_local std::vector<PathVertex> camera_path, light_path;
  thread_local std::vector<Color> emitted;
  const size_t capacity = size_t(settings_.max_bounces) + 2;
  if (camera_path.size() < capacity) { camera_path.resize(capacity); light_path.resize(capacity); }
  emitted.assign(capacity, Color(0.0f));

  // The AOVs, data and colour passes, unless the caller makes its own (FirstHit::aovs).
  const bool aovs = first_hit && first_hit->aovs;
  DataPassSample data;  // the data passes (film/data_passes.h), gathered by the camera walk
  if (first_hit) {
    data.denoising.active = first_hit->data.denoising.active;
    data.aovs.start(first_hit->data.aovs.layout);
    data.crypto.start(first_hit->data.crypto.layout);
  }
  int nc = camera_subpath<kMedia>(camera_ray, sampler, stats, camera_path.data(), emitted.data(), -1,
                                  aovs ? &data : nullptr);
  // Shadow catchers (shadow_catcher.cpp): the sample's catcher values (kept here: *first_hit
  // is overwritten below), the camera vertex where it splits (-1: none), and its matte.
  // A contribution whose last camera vertex (or, for a lamp passed, the vertex before it)
  // is at or past the split is Combined's only; the rest is the matte's too.
  CatcherSample *const catcher = kCatcher ? first_hit->catcher : nullptr;
  const int split = kCatcher ? split_vertex(camera_path.data(), nc) : -1;
  auto past_split = [split](int vertex) { return kCatcher && split >= 0 && vertex >= split; };
  Color matte(0.0f);
  Color L(0.0f);  // starts with the lamps and volume emission the camera path passed
  for (int n = 0; n < int(emitted.size()); ++n) {
    L += emitted[n];
    if (kCatcher && !past_split(n)) matte += emitted[n];
  }
  // (Kept here: *first_hit is overwritten with the first surface's AOVs below.)
  LightPassSample *const passes = first_hit ? first_hit->passes : nullptr;
  // Strategy passes (film/strategy_passes.h): each contribution's strategy, as it enters L.
  const StrategyPasses strategy_layout = first_hit ? first_hit->strategy_layout : StrategyPasses{};
  Color *const strategies = first_hit ? first_hit->strategies : nullptr;
  if (strategies)  // the lamps and volume emission the camera path passed: s = 0, t = n + 2
    for (int n = 0; n < int(emitted.size()); ++n) strategies[strategy_layout.index(0, n + 2)] += emitted[n];
  PassCache first_split;
  if (passes) {  // light passes (light_passes.cpp): the colours, and the emission passed
    first_split = pass_cache(camera_path.data(), nc);
    if (aovs) add_color_passes(data, *passes);
    for (int n = 0; n < int(emitted.size()); ++n) {
      if (is_black(emitted[n]) || past_split(n)) continue;  // none past a split, as Cycles
      PassClass pc = pass_class(light_path.data(), camera_path.data(), 0, n + 2, Vec3(0.0f), first_split);
      passes->add(emitted[n], pc.scatterings, pc.first);
    }
  }
  if (aovs) {
    *first_hit = first_surface(camera_path.data(), nc);
    first_hit->data = data;
    if (settings_.alpha.tracked()) first_hit->transparency = transparency(camera_path.data(), nc);
  }
  int nl = light_subpath<kMedia>(sampler, stats, light_path.data());

  const bool one_strategy = settings_.strategy_s >= 0;
  // s = 1 samples its own light point: it runs even when the light subpath failed
  // (a volume light's point outside its medium), or it would be biased by that failure.
  const int s_max = std::max(nl, 1);
  for (int t = 1; t <= nc; ++t) {
    for (int s = 0; s <= s_max; ++s) {
      int depth = s + t - 2;
      if ((s == 1 && t == 1) || depth < 0 || depth > settings_.max_bounces) continue;
      if (one_strategy && (s != settings_.strategy_s || t != settings_.strategy_t)) continue;
      Vec2 raster;
      float w = 1;
      Vec3 connection_dir(0.0f);
      Color c = connect<kMedia>(light_path.data(), camera_path.data(), s, t, sampler, stats, &raster, &w,
                                passes ? &connection_dir : nullptr);
      if (one_strategy && settings_.strategy_unweighted && w > 0) c = c / w;
      if (!is_finite(c) || is_black(c)) continue;
      const int k = strategies ? strategy_layout.index(s, t) : -1;  // its strategy pass
      // Light tracing reaches the camera straight from its light vertex: past a split when
      // that vertex is on a catcher (the camera ray through its pixel meets it first).
      const bool caught = kCatcher && (t == 1 ? light_path[s - 1].catcher : past_split(t - 1));
      PassClass pc;
      if (passes && !caught) pc = pass_class(light_path.data(), camera_path.data(), s, t, connection_dir, first_split);
      if (t == 1) splats.push_back({raster, c, k >= 0 ? uint8_t(k) : Splat::kNoStrategy,
                                    {pc.first, passes != nullptr && !caught, pc.scatterings > 1},
                                    kCatcher && !caught ? CatcherSplat::CombinedAndMatte : CatcherSplat::Combined});
      else L += c;
      if (strategies && t > 1) strategies[k] += c;
      if (passes && t > 1 && !caught) add_light_pass(camera_path.data(), s, t, pc, c, *passes);
      if (kCatcher && t > 1 && !caught) matte += c;
    }
  }
  if constexpr (kCatcher) {
    // The matte: what the sample added before its split, or all of it; its camera side.
    catcher->matte = matte;
    camera_catcher_values(camera_path.data(), nc, split, *catcher);
    // The catcher pass: the sample's copy (the subpaths' storage is free again).
    catcher->catcher = catcher_pass<kMedia>(camera_ray, sampler, stats, split, camera_path.data(), light_path.data(),
                                            emitted.data(), capacity, splats);
  }
  return L;
}

}  // namespace rdv::bdpt
