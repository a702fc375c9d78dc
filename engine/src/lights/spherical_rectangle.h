// A rectangle sampled by the solid angle it subtends from a point (Urena, Fajardo and King
// 2013, "An Area-Preserving Parametrization for Spherical Rectangles"): every direction
// toward the rectangle is equally likely, so the 1 / r^2 and the lamp-side cosine that
// uniform area sampling leaves in a lamp's estimate (noise under a large lamp close to a
// surface) are gone. In double: the solid angle is the sum of four angles less 2 pi, which
// cancels in float for a rectangle that looks small.
#pragma once
#include "core/math.h"

namespace rdv {

class SphericalRectangle {
 public:
  // The rectangle corner + [0, 1] ex + [0, 1] ey (ex and ey orthogonal) seen from `from`.
  SphericalRectangle(Vec3 from, Vec3 corner, Vec3 ex, Vec3 ey);
  // Steradians; 0 when `from` lies in the rectangle's plane.
  double solid_angle() const { return solid_angle_; }
  // The point of the rectangle in direction u of [0, 1)^2, uniform in solid angle (density
  // 1 / solid_angle()). Only for a solid angle > 0.
  Vec3 sample(Vec2 u) const;

 private:
  Vec3 from_, x_, y_, z_;  // the frame: x along ex, y along ey, z away from the plane's far side
  double x0_ = 0, x1_ = 0, y0_ = 0, y1_ = 0, z0_ = 0;  // the rectangle in that frame (z0 <= 0)
  double b0_ = 0, b1_ = 0, k_ = 0, solid_angle_ = 0;
};

}  // namespace rdv
