// Henyey-Greenstein phase function (g in (-1, 1); g = 0 is isotropic), as Cycles'
// Volume Scatter / Principled Volume anisotropy. Directions point away from the
// scattering point: wo toward where the light goes, wi toward where it comes from.
#pragma once
#include "core/math.h"

namespace rdv {

struct HenyeyGreenstein {
  float g = 0;

  // Density of scattering from wi into wo; cos_theta = dot(wo, -wi)... see below.
  static float density(float cos_theta, float g) {
    float denom = 1.0f + g * g + 2.0f * g * cos_theta;
    return kInv4Pi * (1.0f - g * g) / (denom * safe_sqrt(denom));
  }
  // p(wo, wi) with both directions pointing away from the point: forward scattering
  // (g > 0) means wi close to -wo.
  float eval(Vec3 wo, Vec3 wi) const { return density(dot(wo, wi), g); }
  float pdf(Vec3 wo, Vec3 wi) const { return eval(wo, wi); }
  // Samples wi given wo; the weight p / pdf is exactly 1.
  Vec3 sample(Vec3 wo, Vec2 u) const {
    float cos_theta;
    if (std::fabs(g) < 1e-3f) {
      cos_theta = 1.0f - 2.0f * u.x;
    } else {
      float sq = (1.0f - g * g) / (1.0f + g - 2.0f * g * u.x);
      cos_theta = -(1.0f + g * g - sq * sq) / (2.0f * g);
    }
    cos_theta = clampf(cos_theta, -1.0f, 1.0f);
    float sin_theta = safe_sqrt(1.0f - cos_theta * cos_theta), phi = 2.0f * kPi * u.y;
    Frame f(wo);
    // cos_theta is measured against wo (the density uses dot(wo, wi)).
    return f.to_world(Vec3(sin_theta * std::cos(phi), sin_theta * std::sin(phi), cos_theta));
  }
};

}  // namespace rdv
