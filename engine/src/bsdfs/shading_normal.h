// Keeping shading normals usable (no black terminator). A normal from interpolation,
// a normal map or bump can tilt so far that the mirror reflection of the view
// direction goes below the geometric surface; the surface would then turn black at
// grazing views. Cycles bends such a normal just enough that the reflection stays
// above the surface (ensure_valid_reflection, intern/cycles/kernel/geom/...); we do
// the same. Light leaks are prevented separately: the Bsdf only scatters to directions
// on which the geometric and shading normals agree.
#pragma once
#include "core/math.h"

namespace rdv {

// ng: geometric normal on the viewer's side; wo: toward the viewer; n: shading normal
// on ng's side. Returns a unit normal whose reflection of wo is above the surface.
inline Vec3 ensure_valid_reflection(Vec3 ng, Vec3 wo, Vec3 n) {
  Vec3 r = n * (2.0f * dot(n, wo)) - wo;
  float threshold = std::min(0.9f * dot(ng, wo), 0.01f);
  if (dot(ng, r) >= threshold) return n;
  float n_ng = dot(n, ng);
  Vec3 x = n - ng * n_ng;
  float len = length(x);
  if (!(len > 0)) return ng;
  x = x / len;
  float ix = dot(wo, x), iz = dot(wo, ng);
  float ix2 = ix * ix, iz2 = iz * iz, a = ix2 + iz2;
  float b = safe_sqrt(ix2 * (a - threshold * threshold));
  float c = iz * threshold + a;
  float fac = 0.5f / a;
  float n1_z2 = fac * (b + c), n2_z2 = fac * (-b + c);
  bool valid1 = n1_z2 > 1e-5f && n1_z2 <= 1.0f + 1e-5f;
  bool valid2 = n2_z2 > 1e-5f && n2_z2 <= 1.0f + 1e-5f;
  float nx, nz;
  if (valid1 && valid2) {
    float n1x = safe_sqrt(1 - n1_z2), n1z = safe_sqrt(n1_z2), n2x = safe_sqrt(1 - n2_z2), n2z = safe_sqrt(n2_z2);
    float r1 = 2 * (n1x * ix + n1z * iz) * n1z - iz, r2 = 2 * (n2x * ix + n2z * iz) * n2z - iz;
    valid1 = r1 >= 1e-5f;
    valid2 = r2 >= 1e-5f;
    bool pick1 = (valid1 && valid2) ? r1 < r2 : r1 > r2;
    nx = pick1 ? n1x : n2x;
    nz = pick1 ? n1z : n2z;
  } else if (valid1 || valid2) {
    float z2 = valid1 ? n1_z2 : n2_z2;
    nx = safe_sqrt(1 - z2);
    nz = safe_sqrt(z2);
  } else {
    return ng;
  }
  return normalize(x * nx + ng * nz);
}

}  // namespace rdv
