// Blackbody emission as Cycles' Principled Volume computes it (Blender 3.4,
// svm_node_principled_volume): radiance per unit length
//   tint * sigma/pi * 1e-6 * mix(1, T^4, intensity) * colour(T),   sigma = 5.670373e-8
// where colour(T) is the chromaticity of Planck's spectrum at temperature T in linear
// Rec.709, scaled to luminance 1 (negative components clipped). Like Cycles, emission
// below 1e-5 (its closure cutoff) is dropped, so T = 0 (outside a temperature grid)
// does not glow.
#pragma once
#include "core/math.h"

namespace rdv {

// Rec.709 colour of a blackbody at T kelvin, luminance 1; constant below 800 K and above
// 12000 K (as Cycles clamps its fit).
Color blackbody_color(float kelvin);

struct Blackbody {
  float intensity = 0;  // Cycles' "Blackbody Intensity" (1: physically based)
  Color tint{1.0f};
  bool active() const { return intensity > 0; }
  Color radiance(float kelvin) const;
};

}  // namespace rdv
