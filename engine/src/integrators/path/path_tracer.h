// Unidirectional path tracing with next-event estimation, multiple importance
// sampling (power heuristic) between light and BSDF sampling, and Russian roulette;
// with homogeneous participating media when the scene has them (distance sampling,
// phase-function NEE through media and index-matched boundaries).
// The reference every other integrator is checked against.
#pragma once
#include "integrators/path/shadow_catcher.h"
#include "integrators/tile_integrator.h"

namespace rdv {

class PathTracer final : public TileIntegrator {
 public:
  PathTracer(const Scene &scene, int max_bounces, const LightPathLimits &limits = {}, const FilmAlpha &alpha = {})
      : scene_(scene), max_bounces_(max_bounces), limits_(limits), alpha_(alpha) {}
  Color Li(const CameraRay &camera_ray, Sampler &sampler, RayStats &stats, FirstHit *first_hit,
           std::vector<Splat> &splats) const override;

 private:
  // The path loop, compiled for scenes with participating media and without (a scene
  // without media runs no medium code at all), and for each role (shadow_catcher.h): None
  // (no shadow catcher: none of their code), a sample's path in a scene with one (Main),
  // its copy (Copy: returns the catcher pass's value).
  // Li in a scene with a shadow catcher (first_hit->catcher set): the sample, then its copy.
  [[gnu::noinline]] Color Li_with_catcher(const CameraRay &camera_ray, Sampler &sampler, RayStats &stats,
                                          FirstHit *first_hit) const;
  template <bool kMedia, shadow_catcher::Role kRole>
  Color trace(const CameraRay &camera_ray, Sampler &sampler, RayStats &stats, FirstHit *first_hit) const;
  const Scene &scene_;
  int max_bounces_;
  LightPathLimits limits_;
  FilmAlpha alpha_;
};

}  // namespace rdv
