// Cycles' Ambient Occlusion node: the share of directions around the normal in which
// nothing lies within a distance, traced by the scene (textures/texture_rays.h).
#pragma once
#include "core/math.h"

namespace rdv {

struct ShadingPoint;

// The unoccluded share of `samples` directions, cosine-distributed around n (the shading
// normal on the side of the ray that reached the point, as Cycles'), within `distance` (1
// without a scene to ask, a distance or samples below 1, as Cycles). The directions are a
// fixed set per point (PointSampleSet). The side is the reaching ray's: a light subpath's
// for BDPT's light vertices, the camera's own side wherever light reflects (not through a
// surface that transmits, where the two sides' AO differ).
float ambient_occlusion(const ShadingPoint &sp, Vec3 n, float distance, int samples, bool only_local);

}  // namespace rdv
