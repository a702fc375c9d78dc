// Index-matched medium boundaries that coincide with real surfaces. A smoke or fire
// domain's box standing on the floor has its bottom face in the floor's plane; which of
// the two a ray meets first is then a matter of rounding, and stepping past the
// boundary (the origin offset of core/ray_offset.h) stepped past the floor too: paths
// fell through the floor, and light subpaths lost the medium they started in.
//
// pbrt-v4 (SurfaceInteraction::SkipIntersection) and Mitsuba 3 (spawn_ray past a null
// BSDF) step past such boundaries the same way; Cycles skips the primitive it leaves
// (ray.self) instead of offsetting. Here boundaries have BVHs of their own, and the
// order is decided with the offset itself: the boundary comes first only if the ray
// spawned past it would still meet the surface; otherwise the surface is the hit and
// carries the boundary along (CoincidentBoundary), to be crossed only by paths that
// go on through the surface. Deciding with spawn_origin keeps it exactly as robust as
// the offsets are, from millimetre to kilometre scenes.
#include "core/ray_offset.h"
#include "scene/scene.h"

namespace rdv {

// Whether a ray along d leaving `from` (a surface point with normal ng, offset to d's
// side) starts beyond the plane of `other`: it would never meet `other`.
static bool steps_past(const SurfaceHit &from, const SurfaceHit &other, Vec3 d) {
  Vec3 o = spawn_origin(from.p, from.ng, from.error, d);
  return dot(o - other.p, other.ng) * dot(d, other.ng) >= 0;
}

bool Scene::intersect_with_boundaries(const Ray &ray, const RawHit *surface, SurfaceHit &hit,
                                      CoincidentBoundary &coincident) const {
  RawHit raw;
  if (!accel_.intersect_boundary(ray, raw)) {
    if (surface) surface_at(*surface, hit);
    return surface != nullptr;
  }
  if (!surface) {
    surface_at(raw, hit);
    return true;
  }
  SurfaceHit boundary;
  surface_at(raw, boundary);
  surface_at(*surface, hit);
  bool on_surface = boundary.t <= hit.t ? steps_past(boundary, hit, ray.d) : steps_past(hit, boundary, ray.d);
  if (on_surface) {
    coincident.material = int(boundary.material);
    coincident.ng = boundary.ng;
  } else if (boundary.t <= hit.t) {
    hit = boundary;
  }
  return true;
}

}  // namespace rdv
