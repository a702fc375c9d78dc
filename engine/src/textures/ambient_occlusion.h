// Cycles' Ambient Occlusion node: the share of directions around the normal in which
// nothing lies within a distance. The rays are the scene's to trace: a texture asks through
// OcclusionQuery (textures sit below the scene), which Scene::shading_point hands it.
#pragma once
#include "core/math.h"

namespace rdv {

struct ShadingPoint;

class OcclusionQuery {
 public:
  virtual ~OcclusionQuery() = default;
  // Whether a ray leaving the shading point along d meets a surface within tmax (only_local:
  // a surface of the point's own object; else any that shadow rays meet).
  virtual bool texture_ray_occluded(const ShadingPoint &sp, Vec3 d, float tmax, bool only_local) const = 0;
};

// The unoccluded share of `samples` directions, cosine-distributed around n (the shading
// normal on the side of the ray that reached the point, as Cycles'), within
// `distance` (1 without a scene to ask, a distance or samples below 1, as Cycles). Cycles
// draws the directions at random for every evaluation; here they are a stratified set
// rotated by a hash of the point's position, a fixed function of the point (a path's
// contribution must be one function of its vertices, docs/mlt.md): the same distribution per
// evaluation, so images agree in expectation. The side is the reaching ray's: a light
// subpath's for BDPT's light vertices, the camera's own side wherever light reflects (not
// through a surface that transmits, where the two sides' AO differ).
float ambient_occlusion(const ShadingPoint &sp, Vec3 n, float distance, int samples, bool only_local);

}  // namespace rdv
