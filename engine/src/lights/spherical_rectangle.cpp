#include "lights/spherical_rectangle.h"
#include <algorithm>
#include <cmath>

namespace rdv {

namespace {
struct D3 { double x, y, z; };
D3 normalized(double x, double y, double z) {
  const double l = std::sqrt(x * x + y * y + z * z);
  return l > 0 ? D3{x / l, y / l, z / l} : D3{0, 0, 0};
}
double dot(D3 a, D3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
double angle_between_normals(D3 a, D3 b) { return std::acos(std::clamp(-dot(a, b), -1.0, 1.0)); }
double dot_double(Vec3 a, Vec3 b) { return double(a.x) * b.x + double(a.y) * b.y + double(a.z) * b.z; }
}  // namespace

SphericalRectangle::SphericalRectangle(Vec3 from, Vec3 corner, Vec3 ex, Vec3 ey) : from_(from) {
  const float ex_len = length(ex), ey_len = length(ey);
  if (!(ex_len > 0) || !(ey_len > 0)) return;
  x_ = ex / ex_len;
  y_ = ey / ey_len;
  z_ = cross(x_, y_);
  const Vec3 d = corner - from;
  z0_ = dot_double(d, z_);
  if (z0_ > 0) {  // the frame's z away from the rectangle: z0 < 0
    z_ = -z_;
    z0_ = -z0_;
  }
  if (!(z0_ < 0)) return;  // in the plane: it subtends nothing
  x0_ = dot_double(d, x_);
  y0_ = dot_double(d, y_);
  x1_ = x0_ + ex_len;
  y1_ = y0_ + ey_len;
  // The normals of the four great circles through the corners' directions, and the
  // spherical rectangle's inner angles between them.
  const D3 n0 = normalized(0, z0_, -y0_), n1 = normalized(-z0_, 0, x1_), n2 = normalized(0, -z0_, y1_),
           n3 = normalized(z0_, 0, -x0_);
  const double g0 = angle_between_normals(n0, n1), g1 = angle_between_normals(n1, n2),
               g2 = angle_between_normals(n2, n3), g3 = angle_between_normals(n3, n0);
  b0_ = n0.z;
  b1_ = n2.z;
  k_ = 2 * M_PI - g2 - g3;
  solid_angle_ = std::max(g0 + g1 - k_, 0.0);
}

Vec3 SphericalRectangle::sample(Vec2 u) const {
  // The x of the point: the area swept from the rectangle's left edge is u.x of the whole.
  const double au = double(u.x) * solid_angle_ + k_;
  const double sin_au = std::sin(au);
  const double fu = (std::cos(au) * b0_ - b1_) / (sin_au != 0 ? sin_au : 1e-300);
  const double cu = std::clamp(std::copysign(1.0, fu) / std::sqrt(fu * fu + b0_ * b0_), -1.0, 1.0);
  const double sin_cu = std::sqrt(std::max(1.0 - cu * cu, 0.0));
  double xu = sin_cu > 0 ? -(cu * z0_) / sin_cu : (cu * z0_ <= 0 ? x1_ : x0_);
  xu = std::clamp(std::isfinite(xu) ? xu : 0.5 * (x0_ + x1_), x0_, x1_);
  // Its y: uniform in the cosine-weighted height along that line of the rectangle.
  const double dist = std::sqrt(xu * xu + z0_ * z0_);
  const double h0 = y0_ / std::sqrt(dist * dist + y0_ * y0_), h1 = y1_ / std::sqrt(dist * dist + y1_ * y1_);
  const double hv = h0 + double(u.y) * (h1 - h0), hv2 = hv * hv;
  double yv = hv2 < 1.0 - 1e-12 ? (hv * dist) / std::sqrt(1.0 - hv2) : y1_;
  yv = std::clamp(yv, y0_, y1_);
  return from_ + x_ * float(xu) + y_ * float(yv) + z_ * float(z0_);
}

}  // namespace rdv
