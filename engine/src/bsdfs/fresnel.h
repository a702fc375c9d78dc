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

}  // namespace rdv
