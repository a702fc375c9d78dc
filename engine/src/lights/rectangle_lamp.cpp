#include "lights/rectangle_lamp.h"
#include <algorithm>
#include "lights/spherical_rectangle.h"

namespace rdv {

namespace {

struct Rectangle {
  Vec3 corner, ex, ey;  // corner + [0, 1] ex + [0, 1] ey
  float area() const { return length(ex) * length(ey); }
};

// The part of the lamp that can light ref (the whole lamp without a spread); false: none.
bool lit_part(const Light &l, Vec3 ref, Rectangle &r) {
  const Vec3 to_ref = ref - l.position;
  const float height = dot(to_ref, l.axis);
  if (!(height > 0)) return false;  // behind the emitting side, or in its plane
  if (l.tan_spread <= 0) {
    r = {l.position - l.edge_u * 0.5f - l.edge_v * 0.5f, l.edge_u, l.edge_v};
    return true;
  }
  const float radius = height / l.tan_spread;  // tan_spread = 1 / tan(spread / 2)
  const float len_u = length(l.edge_u), len_v = length(l.edge_v);
  const Vec3 u = l.edge_u / len_u, v = l.edge_v / len_v;
  const float foot_u = dot(to_ref, u), foot_v = dot(to_ref, v);
  const float min_u = std::max(foot_u - radius, -0.5f * len_u), max_u = std::min(foot_u + radius, 0.5f * len_u);
  const float min_v = std::max(foot_v - radius, -0.5f * len_v), max_v = std::min(foot_v + radius, 0.5f * len_v);
  if (!(min_u < max_u) || !(min_v < max_v)) return false;
  r = {l.position + u * min_u + v * min_v, u * (max_u - min_u), v * (max_v - min_v)};
  return true;
}

// Area density converted to solid angle at ref.
float area_to_solid_angle(const Light &l, const Rectangle &r, Vec3 ref, Vec3 p) {
  const Vec3 d = p - ref;
  const float dist2 = length_squared(d), cos_l = -dot(l.axis, d) / std::sqrt(dist2);
  return cos_l > 0 && dist2 > 0 ? dist2 / (r.area() * cos_l) : 0.0f;
}

}  // namespace

bool sample_rectangle_lamp_from(const Light &l, Vec3 ref, Vec2 u, Vec3 &p, float &pdf) {
  Rectangle r;
  if (!lit_part(l, ref, r)) return false;
  const SphericalRectangle seen(ref, r.corner, r.ex, r.ey);
  if (seen.solid_angle() >= kMinSphericalRectangle) {
    p = seen.sample(u);
    pdf = float(1.0 / seen.solid_angle());
  } else {
    p = r.corner + r.ex * u.x + r.ey * u.y;
    pdf = area_to_solid_angle(l, r, ref, p);
  }
  return pdf > 0 && std::isfinite(pdf);
}

float rectangle_lamp_pdf(const Light &l, Vec3 ref, Vec3 p) {
  Rectangle r;
  if (!lit_part(l, ref, r)) return 0.0f;
  if (l.tan_spread > 0) {  // outside the part (it is all of a lamp without a spread): never chosen
    const Vec3 q = p - r.corner;
    const float x = dot(q, r.ex) / length_squared(r.ex), y = dot(q, r.ey) / length_squared(r.ey);
    constexpr float kEdge = 1e-5f;  // the hit point's rounding
    if (x < -kEdge || x > 1 + kEdge || y < -kEdge || y > 1 + kEdge) return 0.0f;
  }
  const SphericalRectangle seen(ref, r.corner, r.ex, r.ey);
  if (seen.solid_angle() >= kMinSphericalRectangle) return float(1.0 / seen.solid_angle());
  return area_to_solid_angle(l, r, ref, p);
}

}  // namespace rdv
