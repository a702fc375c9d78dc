// Cycles 3.4's shadow catcher in BDPT: the path tracer's three sums (integrators/path/
// shadow_catcher.h, film/shadow_catcher_passes.h) from bidirectional samples.
//
// A path belongs to the catcher's side when the camera's see-through chain (the camera ray,
// on through lamps, Transparent BSDFs and, with Transparent Glass, smooth refractions)
// meets a shadow catcher that is no holdout object before the path ends; the camera
// subpath's first such vertex is the sample's split. Every strategy makes paths of one
// side only:
// - (s, t >= 2): past the split when its last camera vertex camera_path[t - 1] is at or
//   past it (the vertices before the split are delta: no strategy connects there);
//   lamps and volume emission the camera walk passes, when the segment leaves a vertex at
//   or past it;
// - t = 1 (light tracing): past the split when its light vertex is on a catcher: the
//   camera sees that vertex straight along the connection, so the camera ray through the
//   pixel it lands on meets the catcher there first (its splat is not the matte's).
// Combined (C) is the sample as ever, the catcher an ordinary object; the matte (M) is
// what is not past the split (its splats carry CatcherSplat::CombinedAndMatte); at the split the camera
// subpath's throughput joins the matte's transparency.
// The catcher pass (S) is the sample's copy (catcher_pass), its random numbers the
// sample's (every decision draws at the dimensions of its vertex): a light subpath from the
// lights of the catcher pass (Light::shadow_catcher) meeting shadow catchers only, traced
// for every sample as the main one is; its light tracing from catcher vertices, the camera
// ray to them checked against the whole scene (the copy's prefix: the pixel's camera ray
// meets the catcher there first), splats to the catcher pass alone (CatcherSplat::Pass);
// when the sample split, its camera subpath traced again (its prefix is the main one's,
// bit for bit), meeting shadow catchers only from the split on, and every strategy whose
// last camera vertex is at or past the split, with shadow rays and connections that meet
// catchers only. The copy has the main sample's strategies and MIS weights: where nothing
// but catchers is in the way (a lit floor), its paths are the main sample's and S equals
// C - M, so the pass is 1 there up to rounding, as the path tracer's is, not noise around 1
// (which the approximate shadow catcher's clamp would turn into a faint shadow).
// A scene without a catcher runs none of this (Bdpt::li<kMedia, false>); a sample that
// does not split traces only its copy's light subpath (few rays: it meets catchers only).
#include "integrators/bdpt/sample_loop.h"

namespace rdv::bdpt {

int Bdpt::split_vertex(const PathVertex *camera_path, int n) const {
  for (int i = 1; i < n; ++i) {
    const PathVertex &v = camera_path[i];
    if (!v.see_through) return -1;
    if (v.catcher) return i;
  }
  return -1;
}

void Bdpt::camera_catcher_values(const PathVertex *camera_path, int n, int split, CatcherSample &catcher) const {
  // At the split the throughput joins the matte's transparency (the catcher is a hole in it).
  catcher.split = split >= 0;
  catcher.matte_transparency =
      split >= 0 ? transparency(camera_path, split) + average(camera_path[split].beta) : transparency(camera_path, n);
  // Cycles' background pass, with an opaque film: the world behind the catcher along the
  // ray that met it, or the world the camera sees through to.
  if (!settings_.alpha.film_transparent) {
    if (split >= 0) {
      const PathVertex &v = camera_path[split];
      catcher.background = v.beta * background_along(-v.wo, camera_path[split - 1].out_mask);
    } else if (n >= 2 && camera_path[n - 1].infinite && camera_path[n - 1].see_through) {
      const PathVertex &v = camera_path[n - 1];
      catcher.background = v.beta * background_along(v.dir, camera_path[n - 2].out_mask);
    }
  }
}

void Bdpt::camera_catcher_values(const PathVertex *camera_path, int n, CatcherSample &catcher) const {
  camera_catcher_values(camera_path, n, split_vertex(camera_path, n), catcher);
}

Color Bdpt::background_along(Vec3 dir, uint32_t mask) const {
  Color L(0.0f);
  for (uint32_t li : scene_.infinite_lights()) {
    const Light &light = scene_.lights()[li];
    if (light.type == LightType::Background && (light.visibility & mask)) L += infinite_light_radiance(light, dir);
  }
  return L;
}

template <bool kMedia>
Color Bdpt::catcher_pass(const CameraRay &camera_ray, Sampler &sampler, RayStats &stats, int split,
                         PathVertex *camera_path, PathVertex *light_path, Color *emitted, size_t capacity,
                         std::vector<Splat> &splats) const {
  // The copy's light subpath, for every sample (one per camera sample, as the main one's):
  // its light tracing lands where the camera sees the catcher.
  const int nl = light_subpath<kMedia>(sampler, stats, light_path, -1, true);
  const bool one_strategy = settings_.strategy_s >= 0;
  for (int s = 2; s <= nl && s - 1 <= settings_.max_bounces; ++s) {
    if (one_strategy && (s != settings_.strategy_s || settings_.strategy_t != 1)) continue;
    Vec2 raster;
    float w = 1;
    Color c = connect<kMedia>(light_path, camera_path, s, 1, sampler, stats, &raster, &w, nullptr, true);
    if (one_strategy && settings_.strategy_unweighted && w > 0) c = c / w;
    if (is_finite(c) && !is_black(c)) splats.push_back({raster, c, Splat::kNoStrategy, {}, CatcherSplat::Pass});
  }
  Color S(0.0f);
  if (split < 0) return S;
  // The camera subpath again: its prefix is the main one's, so it splits where that did.
  std::fill_n(emitted, capacity, Color(0.0f));
  const int nc = camera_subpath<kMedia>(camera_ray, sampler, stats, camera_path, emitted, -1, nullptr, false, true);
  if (split_vertex(camera_path, nc) != split) return S;  // (never: the same decisions at the same dimensions)
  for (int n = split; n < int(capacity); ++n) S += emitted[n];
  const int s_max = std::max(nl, 1);
  for (int t = split + 1; t <= nc; ++t) {
    for (int s = 0; s <= s_max; ++s) {
      if (s + t - 2 > settings_.max_bounces) continue;
      if (one_strategy && (s != settings_.strategy_s || t != settings_.strategy_t)) continue;
      Vec2 raster;
      float w = 1;
      Color c = connect<kMedia>(light_path, camera_path, s, t, sampler, stats, &raster, &w, nullptr, true);
      if (one_strategy && settings_.strategy_unweighted && w > 0) c = c / w;
      if (is_finite(c)) S += c;
    }
  }
  return S;
}

template <bool kMedia>
Color Bdpt::catcher_strategy(const CameraRay &camera_ray, Sampler &sampler, RayStats &stats, int s, int t, int split,
                             PathVertex *camera_path, PathVertex *light_path, Color *emitted, size_t capacity,
                             Vec2 *raster) const {
  // The copy's light subpath, drawn where the main one's was (the same numbers).
  auto copy_light_subpath = [&] {
    return s < 2 || light_subpath<kMedia>(sampler, stats, light_path, s, true) == s;
  };
  if (t == 1) {  // light tracing from a catcher, every sample (catcher_pass)
    if (s < 2 || !copy_light_subpath()) return Color(0.0f);
    return connect<kMedia>(light_path, camera_path, s, 1, sampler, stats, raster, nullptr, nullptr, true);
  }
  if (split < 0 || t - 1 < split) return Color(0.0f);  // a strategy of the copy's only from the split on
  std::fill_n(emitted, capacity, Color(0.0f));
  const int nc = camera_subpath<kMedia>(camera_ray, sampler, stats, camera_path, emitted, t, nullptr, false, true);
  if (split_vertex(camera_path, nc) != split) return Color(0.0f);  // (never: its prefix is the main one's)
  if (s == 0) {
    Color c = t - 2 >= split ? emitted[t - 2] : Color(0.0f);  // a lamp passed past the split
    if (nc == t) c += connect<kMedia>(light_path, camera_path, 0, t, sampler, stats, raster, nullptr, nullptr, true);
    return c;
  }
  if (nc != t || !copy_light_subpath()) return Color(0.0f);
  return connect<kMedia>(light_path, camera_path, s, t, sampler, stats, raster, nullptr, nullptr, true);
}

template Color Bdpt::catcher_strategy<false>(const CameraRay &, Sampler &, RayStats &, int, int, int, PathVertex *,
                                             PathVertex *, Color *, size_t, Vec2 *) const;
template Color Bdpt::catcher_strategy<true>(const CameraRay &, Sampler &, RayStats &, int, int, int, PathVertex *,
                                            PathVertex *, Color *, size_t, Vec2 *) const;

template Color Bdpt::li<false, true>(const CameraRay &, Sampler &, RayStats &, FirstHit *, std::vector<Splat> &) const;
template Color Bdpt::li<true, true>(const CameraRay &, Sampler &, RayStats &, FirstHit *, std::vector<Splat> &) const;

}  // namespace rdv::bdpt
