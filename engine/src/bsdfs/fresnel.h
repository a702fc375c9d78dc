// Fresnel reflectance terms.
#pragma once
#include <complex>
#include "core/math.h"

namespace rdv {

// Conductor with complex index of refraction eta + i k (per RGB channel).
inline float fresnel_conductor(float cos_i, float eta, float k) {
  using C = std::complex<float>;
  cos_i = clampf(cos_i, 0.0f, 1.0f);
  C n(eta, k);
  float sin2 = 1.0f - cos_i * cos_i;
  C cos_t = std::sqrt(C(1.0f) - C(sin2) / (n * n));
  C r_parl = (n * cos_i - cos_t) / (n * cos_i + cos_t);
  C r_perp = (C(cos_i) - n * cos_t) / (C(cos_i) + n * cos_t);
  return 0.5f * (std::norm(r_parl) + std::norm(r_perp));
}

inline Color fresnel_conductor(float cos_i, Color eta, Color k) {
  return {fresnel_conductor(cos_i, eta.x, k.x), fresnel_conductor(cos_i, eta.y, k.y),
          fresnel_conductor(cos_i, eta.z, k.z)};
}

// Unpolarised Fresnel reflectance of a dielectric interface. cos_i > 0 on the side
// the light arrives from; eta = IOR of the far side / IOR of the near side.
// Total internal reflection returns 1.
inline float fresnel_dielectric(float cos_i, float eta) {
  cos_i = clampf(cos_i, -1.0f, 1.0f);
  if (cos_i < 0) { eta = 1.0f / eta; cos_i = -cos_i; }
  float sin2_t = (1.0f - cos_i * cos_i) / (eta * eta);
  if (sin2_t >= 1.0f) return 1.0f;
  float cos_t = safe_sqrt(1.0f - sin2_t);
  float r_parl = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
  float r_perp = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
  return 0.5f * (r_parl * r_parl + r_perp * r_perp);
}

// Refraction of w (pointing away from the surface, on the side of n) through the
// interface with normal n; eta = IOR of the far side / near side. False on TIR.
inline bool refract(Vec3 w, Vec3 n, float eta, Vec3 &wt) {
  float cos_i = dot(n, w);
  float sin2_t = std::max(0.0f, 1.0f - cos_i * cos_i) / (eta * eta);
  if (sin2_t >= 1.0f) return false;
  float cos_t = std::sqrt(1.0f - sin2_t);
  wt = -w / eta + n * (cos_i / eta - cos_t);
  return true;
}

}  // namespace rdv
