#include "integrators/path/path_tracer.h"
#include "integrators/path/path_trace_loop.h"

namespace rdv {

using shadow_catcher::Role;

// The loop for scenes with shadow catchers lives in shadow_catcher.cpp.
extern template Color PathTracer::trace<false, Role::Main>(const CameraRay &, Sampler &, RayStats &, FirstHit *) const;
extern template Color PathTracer::trace<true, Role::Main>(const CameraRay &, Sampler &, RayStats &, FirstHit *) const;
extern template Color PathTracer::trace<false, Role::Copy>(const CameraRay &, Sampler &, RayStats &, FirstHit *) const;
extern template Color PathTracer::trace<true, Role::Copy>(const CameraRay &, Sampler &, RayStats &, FirstHit *) const;

Color PathTracer::Li(const CameraRay &camera_ray, Sampler &sampler, RayStats &stats, FirstHit *first_hit,
                     std::vector<Splat> &) const {
  // Decided once per sample: a scene without media runs the loop without medium code, and
  // one without shadow catchers the loop without their code.
  if (first_hit && first_hit->catcher) return Li_with_catcher(camera_ray, sampler, stats, first_hit);
  return scene_.has_media() ? trace<true, Role::None>(camera_ray, sampler, stats, first_hit)
                            : trace<false, Role::None>(camera_ray, sampler, stats, first_hit);
}

Color PathTracer::Li_with_catcher(const CameraRay &camera_ray, Sampler &sampler, RayStats &stats,
                                  FirstHit *first_hit) const {
  const Color L = scene_.has_media() ? trace<true, Role::Main>(camera_ray, sampler, stats, first_hit)
                                     : trace<false, Role::Main>(camera_ray, sampler, stats, first_hit);
  // The sample met a shadow catcher: its copy gathers the catcher pass (shadow_catcher.h).
  CatcherSample &catcher = *first_hit->catcher;
  if (catcher.split)
    catcher.catcher = scene_.has_media() ? trace<true, Role::Copy>(camera_ray, sampler, stats, nullptr)
                                         : trace<false, Role::Copy>(camera_ray, sampler, stats, nullptr);
  return L;
}

template Color PathTracer::trace<false, Role::None>(const CameraRay &, Sampler &, RayStats &, FirstHit *) const;
template Color PathTracer::trace<true, Role::None>(const CameraRay &, Sampler &, RayStats &, FirstHit *) const;

}  // namespace rdv
