#include "textures/ambient_occlusion.h"
#include "core/sampling.h"
#include "textures/shading_point.h"
#include "textures/texture_rays.h"

namespace rdv {

float ambient_occlusion(const ShadingPoint &sp, Vec3 n, float distance, int samples, bool only_local) {
  if (!sp.rays || !(distance > 0) || samples < 1) return 1.0f;
  if (!(length_squared(n) > 0)) n = sp.ns;
  const Frame frame(normalize(n));
  const PointSampleSet set(sp.p, 0, samples);
  int unoccluded = 0;
  for (int i = 0; i < samples; ++i) {
    const Vec3 d = frame.to_world(cosine_hemisphere(set[i]));
    if (!sp.rays->texture_ray_occluded(sp, d, distance, only_local)) ++unoccluded;
  }
  return float(unoccluded) / float(samples);
}

}  // namespace rdv
