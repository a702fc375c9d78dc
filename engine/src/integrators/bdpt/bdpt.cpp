#include "integrators/bdpt/bdpt.h"
#include "integrators/bdpt/sample_loop.h"

namespace rdv::bdpt {

// The loop for scenes with a shadow catcher is compiled in shadow_catcher.cpp.
extern template Color Bdpt::li<false, true>(const CameraRay &, Sampler &, RayStats &, FirstHit *,
                                            std::vector<Splat> &) const;
extern template Color Bdpt::li<true, true>(const CameraRay &, Sampler &, RayStats &, FirstHit *,
                                           std::vector<Splat> &) const;

Color Bdpt::Li(const CameraRay &camera_ray, Sampler &sampler, RayStats &stats, FirstHit *first_hit,
               std::vector<Splat> &splats) const {
  // Decided once per sample: a scene without media runs no medium code, and one whose film
  // keeps no shadow catcher sums no catcher code.
  if (first_hit && first_hit->catcher)
    return scene_.has_media() ? li<true, true>(camera_ray, sampler, stats, first_hit, splats)
                              : li<false, true>(camera_ray, sampler, stats, first_hit, splats);
  return scene_.has_media() ? li<true, false>(camera_ray, sampler, stats, first_hit, splats)
                            : li<false, false>(camera_ray, sampler, stats, first_hit, splats);
}

FirstHit Bdpt::first_surface(const PathVertex *camera_path, int n) const {
  FirstHit first_hit;
  if (n > 1 && camera_path[1].type == VertexType::Surface) {
    const Camera &cam = scene_.camera_now();
    const PathVertex &v = camera_path[1];
    first_hit.valid = true;
    first_hit.depth = dot(v.p - cam.position(), cam.forward());
    first_hit.normal = v.bsdf.shading_normal(v.wo);  // a normal map's or bump's, as Cycles' Normal pass
    first_hit.albedo = v.bsdf.albedo(v.wo);
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

template Color Bdpt::li<false, false>(const CameraRay &, Sampler &, RayStats &, FirstHit *, std::vector<Splat> &) const;
template Color Bdpt::li<true, false>(const CameraRay &, Sampler &, RayStats &, FirstHit *, std::vector<Splat> &) const;

}  // namespace rdv::bdpt
