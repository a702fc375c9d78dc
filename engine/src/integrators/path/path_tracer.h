// Unidirectional path tracing with next-event estimation, multiple importance
// sampling (power heuristic) between light and BSDF sampling, and Russian roulette.
// The reference every other integrator is checked against.
#pragma once
#include "integrators/integrator.h"

namespace rdv {

class PathTracer final : public Integrator {
 public:
  PathTracer(const Scene &scene, int max_bounces) : scene_(scene), max_bounces_(max_bounces) {}
  Color Li(const CameraRay &camera_ray, Sampler &sampler, RayStats &stats, FirstHit *first_hit,
           std::vector<Splat> &splats) const override;

 private:
  Color sample_direct_light(const SurfaceHit &hit, const Bsdf &bsdf, Vec3 wo, Sampler &sampler,
                            RayStats &stats) const;
  const Scene &scene_;
  int max_bounces_;
};

}  // namespace rdv
