// Self-intersection avoidance that follows the rounding error of each point, so it
// works the same for a millimetre box at the origin, a kilometre terrain and a unit
// box 1e5 units from the origin (pbrt-v3 section 3.9's conservative error bounds).
//
// A surface point is interpolated from its triangle's vertices, moved by its instance
// transform, and the next ray's origin is tested by Embree against the same triangle
// relative to that origin (in object space for instances). Each step rounds at the
// scale of the numbers it handles, coordinate by coordinate, so every surface point
// carries a per-coordinate error bound of a few float ulps of those numbers, and a ray
// leaving it starts that bound's extent along the geometric normal off the surface:
// a box far out along x keeps precise offsets in z. An earlier fixed rule (Waechter & Binder: 256 ulps of each
// coordinate, 1.5e-5 absolute near the origin) moved origins by 1.5% of a millimetre
// box and by half a unit at 3e4 from the origin, through walls and floors.
#pragma once
#include <algorithm>
#include "core/math.h"

namespace rdv {

constexpr float kUlp = 0x1p-24f;  // relative rounding error of one float operation

inline Vec3 vabs(Vec3 v) { return {std::fabs(v.x), std::fabs(v.y), std::fabs(v.z)}; }
inline float max_abs_component(Vec3 v) { return std::max({std::fabs(v.x), std::fabs(v.y), std::fabs(v.z)}); }

// Error bound, per coordinate, of a point interpolated from a triangle's vertices, in
// their space: interpolation rounds each coordinate at the vertices' magnitude in it
// (a floor at z = 0 is exact in z), and Embree's robust test of a ray leaving the point
// against the same triangle rounds at the triangle's extent, in every direction. The
// factors leave room: the acne tests pass with a quarter of them.
inline Vec3 triangle_point_error(Vec3 p0, Vec3 p1, Vec3 p2) {
  Vec3 magnitude = vmax(vabs(p0), vmax(vabs(p1), vabs(p2)));
  Vec3 extent = vmax(p0, vmax(p1, p2)) - vmin(p0, vmin(p1, p2));
  return magnitude * (4 * kUlp) + Vec3(32 * kUlp * max_abs_component(extent));
}

// The same error after an affine transform to world space: the linear part |M| spreads
// the object-space bound, and rounding the world point (and Embree's transform of a
// ray origin back into object space, which mixes coordinates by |M| |M^-1|) adds a few
// ulps of the world coordinates. abs_linear = |M|, mixing = |M| |M^-1|.
inline Vec3 transformed_point_error(Vec3 object_error, Vec3 p_world, const Transform &abs_linear,
                                    const Transform &mixing) {
  return abs_linear.vector(object_error) + mixing.vector(vabs(p_world)) * (4 * kUlp);
}

// The origin of a ray leaving p (per-coordinate error bound `error`) on the side of
// the geometric normal n: moved along n by the error's extent along n.
inline Vec3 offset_ray_origin(Vec3 p, Vec3 n, Vec3 error) {
  float d = std::fabs(n.x) * error.x + std::fabs(n.y) * error.y + std::fabs(n.z) * error.z;
  return p + n * d;
}

// Origin offset to the side of ng that direction d points to.
inline Vec3 spawn_origin(Vec3 p, Vec3 ng, Vec3 error, Vec3 d) {
  return offset_ray_origin(p, dot(ng, d) >= 0 ? ng : -ng, error);
}

// Shadow-ray length that stops short of a target point already moved off its surface,
// by a further relative margin.
inline float shadow_tmax(float distance) { return distance * (1.0f - 2e-4f); }

// The ray that tests whether two points see each other. Each end that lies on a
// surface Embree can hit (nonzero error) moves off it toward the other end;
// the ray runs from one moved point toward the other (not along the unmoved
// direction, which at grazing angles would end within the target's rounding error).
struct ShadowRay {
  Vec3 o, d;
  float tmax = 0;
};
inline ShadowRay shadow_ray(Vec3 from, Vec3 from_ng, Vec3 from_error, Vec3 to, Vec3 to_ng, Vec3 to_error) {
  Vec3 d = to - from;
  Vec3 o = spawn_origin(from, from_ng, from_error, d);
  Vec3 t = spawn_origin(to, to_ng, to_error, -d);
  d = t - o;
  float len = length(d);
  if (!(len > 0)) return {o, Vec3(0, 0, 1), 0.0f};
  return {o, d / len, shadow_tmax(len)};
}
// Toward an infinitely distant light (sun, world) along d.
inline ShadowRay shadow_ray_to_infinity(Vec3 from, Vec3 from_ng, Vec3 from_error, Vec3 d) {
  return {spawn_origin(from, from_ng, from_error, d), d, kInf};
}

}  // namespace rdv
