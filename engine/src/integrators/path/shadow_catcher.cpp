// The path tracer's loop for scenes with a shadow catcher (shadow_catcher.h,
// path_trace_loop.h): the sample's path and its catcher-pass copy.
#include "integrators/path/path_tracer.h"
#include "integrators/path/path_trace_loop.h"

namespace rdv {

using shadow_catcher::Role;

template Color PathTracer::trace<false, Role::Main>(const CameraRay &, Sampler &, RayStats &, FirstHit *) const;
template Color PathTracer::trace<true, Role::Main>(const CameraRay &, Sampler &, RayStats &, FirstHit *) const;
template Color PathTracer::trace<false, Role::Copy>(const CameraRay &, Sampler &, RayStats &, FirstHit *) const;
template Color PathTracer::trace<true, Role::Copy>(const CameraRay &, Sampler &, RayStats &, FirstHit *) const;

}  // namespace rdv
