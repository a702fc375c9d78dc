#include "integrators/bdpt/bdpt.h"
#include "integrators/bdpt/pass_class.h"

namespace rdv::bdpt {

Color Bdpt::Li(const CameraRay &camera_ray, Sampler &sampler, RayStats &stats, FirstHit *first_hit,
               std::vector<Splat> &splats) const {
  // Decided once per sample: a scene without media runs no medium code.
  return scene_.has_media() ? li<true>(camera_ray, sampler, stats, first_hit, splats)
                            : li<false>(camera_ray, sampler, stats, first_hit, splats);
}

FirstHit Bdpt::first_surface(const PathVertex *camera_path, int n) const {
  FirstHit first_hit;
  if (n > 1 && camera_path[1].type == VertexType::Surface) {
    const Camera &cam = scene_.camera_now();
    const PathVertex &v = camera_path[1];
    first_hit.valid = true;
    first_hit.depth = dot(v.p - cam.position(), cam.forward());
    first_hit.normal = dot(v.ns, v.wo) < 0 ? -v.ns : v.ns;
    first_hit.albedo = v.bsdf.albedo();
  }
  return first_hit;
}

float Bdpt::transparency(const PathVertex *camera_path, int n) const {
  float t = 0;
  for (int i = 1; i < n; ++i) {
    const PathVertex &v = camera_path[i];
    if (!v.see_through) break;
    if (v.holdout > 0) t += v.holdout * average(v.beta);
    if (v.infinite && settings_.alpha.film_transparent) t += average(v.beta);
  }
  return t;
}

template <bool kMedia>
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
  if (first_hit) data.denoising.active = first_hit->data.denoising.active;
  int nc = camera_subpath<kMedia>(camera_ray, sampler, stats, camera_path.data(), emitted.data(), -1,
                                  aovs ? &data : nullptr);
  Color L(0.0f);  // starts with the lamps and volume emission the camera path passed
  for (const Color &e : emitted) L += e;
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
    if (aovs) add_color_passes(camera_path.data(), nc, *passes);
    for (int n = 0; n < int(emitted.size()); ++n) {
      if (is_black(emitted[n])) continue;
      PassClass pc = pass_class(light_path.data(), camera_path.data(), 0, n + 2, Vec3(0.0f), first_split);
      passes->add(emitted[n], pc.scatterings, pc.first);
    }
  }
  if (aovs) {
    *first_hit = first_surface(camera_path.data(), nc);
    first_hit->data = data;
    if (settings_.alpha.tracked()) first_hit->transparency = transparency(camera_path.data(), nc);
  }
  int nl = camera_side_only_ ? 0 : light_subpath<kMedia>(sampler, stats, light_path.data());

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
      PassClass pc;
      if (passes) pc = pass_class(light_path.data(), camera_path.data(), s, t, connection_dir, first_split);
      if (t == 1) splats.push_back({raster, c, k >= 0 ? uint8_t(k) : Splat::kNoStrategy,
                                    {pc.first, passes != nullptr, pc.scatterings > 1}});
      else L += c;
      if (strategies && t > 1) strategies[k] += c;
      if (passes && t > 1) add_light_pass(camera_path.data(), s, t, pc, c, *passes);
    }
  }
  return L;
}

}  // namespace rdv::bdpt
