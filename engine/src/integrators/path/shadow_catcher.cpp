// The path tracer's loop for scenes with a shadow catcher (shadow_catcher.h,
// path_trace_loop.h): the sample's path and its catcher-pass copy.
#include "integrators/path/path_tracer.h"
#include "integrators/path/path_trace_loop.h"

namespace rdv {

template Color PathTracer::trace<false, true>(const CameraRay &, Sampler &, RayStats &, FirstHit *,
                                              shadow_catcher::Role) const;
template Color PathTracer::trace<true, true>(const CameraRay &, Sampler &, RayStats &, FirstHit *,
                                             shadow_catcher::Role) const;

}  // namespace rdv
