// The Fresnel equations written out in double precision, for tests to check the engine's
// float Fresnel terms against.
#pragma once
#include <cmath>

namespace rdv::test {

// Unpolarised dielectric reflectance at |cos| c on the side of relative IOR 1, the far side's
// relative IOR eta; 1 past the critical angle.
inline double dielectric_fresnel(double c, double eta) {
  const double s2 = (1 - c * c) / (eta * eta);
  if (s2 >= 1) return 1.0;
  const double t = std::sqrt(1 - s2);
  const double a = (eta * c - t) / (eta * c + t), b = (c - eta * t) / (c + eta * t);
  return 0.5 * (a * a + b * b);
}

}  // namespace rdv::test
