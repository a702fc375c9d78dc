// Self-intersection avoidance that is independent of scene scale (Waechter & Binder,
// "A Fast and Robust Method for Avoiding Self-Intersection", Ray Tracing Gems ch. 6):
// move the origin a fixed number of float ULPs along the geometric normal, so the
// offset grows with |p| and works from millimetre to kilometre scenes alike.
#pragma once
#include <cstring>
#include "core/math.h"

namespace rdv {

inline float int_as_float(int32_t i) { float f; std::memcpy(&f, &i, 4); return f; }
inline int32_t float_as_int(float f) { int32_t i; std::memcpy(&i, &f, 4); return i; }

// n: geometric normal on the side the new ray leaves from.
inline Vec3 offset_ray_origin(Vec3 p, Vec3 n) {
  constexpr float origin = 1.0f / 32.0f;
  constexpr float float_scale = 1.0f / 65536.0f;
  constexpr float int_scale = 256.0f;
  int32_t ix = static_cast<int32_t>(int_scale * n.x);
  int32_t iy = static_cast<int32_t>(int_scale * n.y);
  int32_t iz = static_cast<int32_t>(int_scale * n.z);
  Vec3 pi{int_as_float(float_as_int(p.x) + (p.x < 0 ? -ix : ix)),
          int_as_float(float_as_int(p.y) + (p.y < 0 ? -iy : iy)),
          int_as_float(float_as_int(p.z) + (p.z < 0 ? -iz : iz))};
  return {std::fabs(p.x) < origin ? p.x + float_scale * n.x : pi.x,
          std::fabs(p.y) < origin ? p.y + float_scale * n.y : pi.y,
          std::fabs(p.z) < origin ? p.z + float_scale * n.z : pi.z};
}

// Origin offset to the side of ng that direction d points to.
inline Vec3 spawn_origin(Vec3 p, Vec3 ng, Vec3 d) {
  return offset_ray_origin(p, dot(ng, d) >= 0 ? ng : -ng);
}

// Shadow-ray length that stops short of the target point by the same relative
// margin the origin offset uses.
inline float shadow_tmax(float distance) { return distance * (1.0f - 2e-4f); }

}  // namespace rdv
