// Warps from [0,1)^2 to directions and shapes, each with its pdf.
#pragma once
#include "core/math.h"

namespace rdv {

inline Vec2 concentric_disk(Vec2 u) {
  float ox = 2.0f * u.x - 1.0f, oy = 2.0f * u.y - 1.0f;
  if (ox == 0 && oy == 0) return {0, 0};
  float r, theta;
  if (std::fabs(ox) > std::fabs(oy)) { r = ox; theta = (kPi / 4) * (oy / ox); }
  else { r = oy; theta = kPi / 2 - (kPi / 4) * (ox / oy); }
  return {r * std::cos(theta), r * std::sin(theta)};
}

// Point in a regular polygon of `blades` sides inscribed in the unit circle
// (aperture blades), uniform in area.
inline Vec2 regular_polygon(Vec2 u, int blades, float rotation) {
  float corner = 2.0f * kPi / blades;
  float fi = u.x * blades;
  int tri = std::min(static_cast<int>(fi), blades - 1);
  float a = fi - tri;                        // reuse the remainder as a fresh variate
  float b = u.y;
  if (a + b > 1.0f) { a = 1.0f - a; b = 1.0f - b; }
  float t0 = rotation + corner * tri, t1 = t0 + corner;
  Vec2 p0{std::cos(t0), std::sin(t0)}, p1{std::cos(t1), std::sin(t1)};
  return p0 * a + p1 * b;
}

inline Vec3 cosine_hemisphere(Vec2 u) {
  Vec2 d = concentric_disk(u);
  float z = safe_sqrt(1.0f - d.x * d.x - d.y * d.y);
  return {d.x, d.y, z};
}
inline float cosine_hemisphere_pdf(float cos_theta) { return cos_theta > 0 ? cos_theta * kInvPi : 0.0f; }

inline Vec3 uniform_sphere(Vec2 u) {
  float z = 1.0f - 2.0f * u.x;
  float r = safe_sqrt(1.0f - z * z);
  float phi = 2.0f * kPi * u.y;
  return {r * std::cos(phi), r * std::sin(phi), z};
}
constexpr float uniform_sphere_pdf() { return kInv4Pi; }

// Uniform direction in the cone around axis with cos >= cos_max (density 1 / (2 pi (1 - cos_max))).
inline Vec3 uniform_cone(Vec3 axis, float cos_max, Vec2 u) {
  float c = 1.0f - u.x * (1.0f - cos_max);
  float s = safe_sqrt(1.0f - c * c), phi = 2.0f * kPi * u.y;
  Frame f(axis);
  return f.to_world(Vec3(s * std::cos(phi), s * std::sin(phi), c));
}
inline float uniform_cone_pdf(float cos_max) { return 1.0f / (2.0f * kPi * (1.0f - cos_max)); }

// Barycentrics uniform over a triangle (Heitz's low-distortion square-to-triangle map).
inline Vec2 uniform_triangle(Vec2 u) {
  float b0, b1;
  if (u.x < u.y) { b0 = u.x / 2; b1 = u.y - b0; }
  else { b1 = u.y / 2; b0 = u.x - b1; }
  return {b0, b1};
}

// Written with the ratio of the densities: squaring a solid-angle density of a far
// light (1e23 across a fog bank) would overflow and give inf / inf.
inline float power_heuristic(float pdf_a, float pdf_b) {
  if (!(pdf_a > 0)) return 0.0f;
  if (std::isinf(pdf_a)) return 1.0f;
  float r = pdf_b / pdf_a;
  return 1.0f / (1.0f + r * r);
}

}  // namespace rdv
