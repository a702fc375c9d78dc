#include "integrators/path/path_tracer.h"
#include "integrators/path/path_trace_loop.h"

namespace rdv {

// The loop for scenes with shadow catchers lives in shadow_catcher.cpp.
extern template Color PathTracer::trace<false, true>(const CameraRay &, Sampler &, RayStats &, FirstHit *,
                                                    shadow_catcher::Role) const;
extern template Color PathTracer::trace<true, true>(const CameraRay &, Sampler &, RayStats &, FirstHit *,
                                                   shadow_catcher::Role) const;

Color PathTracer::Li(const CameraRay &camera_ray, Sampler &sampler, RayStats &stats, FirstHit *first_hit,
                     std::vector<Splat> &) const {
  // Decided once per sample: a scene without media runs the loop without medium code, and
  // one without shadow catchers the loop without their code.
  if (first_hit && first_hit->catcher) return Li_with_catcher(camera_ray, sampler, stats, first_hit);
  return scene_.has_media() ? trace<true, false>(camera_ray, sampler, stats, first_hit, shadow_catcher::Role::None)
                            : trace<false, false>(camera_ray, sampler, stats, first_hit, shadow_catcher::Role::None);
}

Color PathTracer::Li_with_catcher(const CameraRay &camera_ray, Sampler &sampler, RayStats &stats,
                                  FirstHit *first_hit) const {
  using shadow_catcher::Role;
  const Color L = scene_.has_media() ? trace<true, true>(camera_ray, sampler, stats, first_hit, Role::Main)
                                     : trace<false, true>(camera_ray, sampler, stats, first_hit, Role::Main);
  // The sample met a shadow catcher: its copy gathers the catcher pass (shadow_catcher.h).
  CatcherSample &catcher = *first_hit->catcher;
  if (catcher.split)
    catcher.catcher = scene_.has_media() ? trace<true, true>(camera_ray, sampler, stats, nullptr, Role::Copy)
                                         : trace<false, true>(camera_ray, sampler, stats, nullptr, Role::Copy);
  return L;
}


template Color PathTracer::trace<false, false>(const CameraRay &, Sampler &, RayStats &, FirstHit *,
                                               shadow_catcher::Role) const;
template Color PathTracer::trace<true, false>(const CameraRay &, Sampler &, RayStats &, FirstHit *,
                                              shadow_catcher::Role) const;

}  // namespace rdv
