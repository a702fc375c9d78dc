// Point and spot lamps with a radius as an emitting sphere (sphere_lamp.h: why, and how
// it is sampled).
#include "lights/sphere_lamp.h"
#include "core/sampling.h"

namespace rdv {

namespace {
// The cosine, to the spot's axis, of the cap of sphere points that can emit into the cone:
// a point of normal n emits along cone directions above its horizon when the angle from
// the axis to n is below pi/2 + the cone's half angle.
float cap_cos(const Light &l) {
  if (l.type != LightType::Spot || l.cos_half_spot <= 0) return -1.0f;  // the whole sphere
  return -safe_sqrt(1.0f - l.cos_half_spot * l.cos_half_spot);          // cos(pi/2 + half angle)
}
}  // namespace

float sample_sphere_lamp_point(const Light &l, Vec2 u, Vec3 &p, Vec3 &n) {
  n = uniform_cone(l.axis, cap_cos(l), u);
  p = l.position + n * l.radius;
  return sphere_lamp_point_pdf(l, n);
}

float sphere_lamp_point_pdf(const Light &l, Vec3 n) {
  const float cos_max = cap_cos(l);
  if (dot(n, l.axis) < cos_max) return 0.0f;
  return 1.0f / (2.0f * kPi * (1.0f - cos_max) * l.radius * l.radius);
}

bool sample_sphere_lamp_direction(const Light &l, Vec3 n, Vec2 u, Vec3 &d) {
  if (l.type == LightType::Spot) d = uniform_cone(l.axis, l.cos_half_spot, u);
  else d = Frame(n).to_world(cosine_hemisphere(u));
  return dot(n, d) > 0;
}

float sphere_lamp_direction_pdf(const Light &l, Vec3 n, Vec3 d) {
  const float c = dot(n, d);
  if (!(c > 0)) return 0.0f;
  if (l.type != LightType::Spot) return cosine_hemisphere_pdf(c);
  return dot(l.axis, d) > l.cos_half_spot ? uniform_cone_pdf(l.cos_half_spot) : 0.0f;
}

Color sphere_lamp_radiance(const Light &l, Vec3 n, Vec3 d, float distance) {
  if (!(dot(n, d) > 0)) return Color(0.0f);
  return lamp_radiance(l, l.position + n * l.radius, d, distance);
}

namespace {
// 1 - cos of the half angle of the cone the sphere subtends from distance^2 d2 > r^2,
// without cancellation for a small far lamp.
float one_minus_cos_max(const Light &l, float d2) {
  const float sin2 = l.radius * l.radius / d2;
  return sin2 / (1.0f + safe_sqrt(1.0f - sin2));
}
}  // namespace

bool sample_sphere_lamp_from(const Light &l, Vec3 ref, Vec2 u, Vec3 &wi, float &dist, float &pdf) {
  const Vec3 to_lamp = l.position - ref;
  const float d2 = length_squared(to_lamp);
  if (!(d2 > l.radius * l.radius)) return false;
  const float d = std::sqrt(d2), omc_max = one_minus_cos_max(l, d2);
  const float omc = u.x * omc_max, c = 1.0f - omc, s = safe_sqrt(omc * (2.0f - omc));
  const float phi = 2.0f * kPi * u.y;
  wi = Frame(to_lamp / d).to_world(Vec3(s * std::cos(phi), s * std::sin(phi), c));
  // Where wi enters the sphere (at the rim, rounding may leave the root slightly negative).
  dist = d * c - safe_sqrt(l.radius * l.radius - d2 * s * s);
  pdf = 1.0f / (2.0f * kPi * omc_max);
  return dist > 0 && std::isfinite(pdf);
}

float sphere_lamp_cone_pdf(const Light &l, Vec3 ref) {
  const float d2 = length_squared(l.position - ref);
  if (!(d2 > l.radius * l.radius)) return 0.0f;
  return 1.0f / (2.0f * kPi * one_minus_cos_max(l, d2));
}

bool intersect_sphere_lamp(const Light &l, Vec3 o, Vec3 d, float tmax, float &t) {
  // |o + t d - c|^2 = r^2 with |d| = 1, in double: o may be far from the lamp.
  const double ox = double(o.x) - l.position.x, oy = double(o.y) - l.position.y, oz = double(o.z) - l.position.z;
  const double b = ox * d.x + oy * d.y + oz * d.z;
  const double c = ox * ox + oy * oy + oz * oz - double(l.radius) * l.radius;
  if (!(c > 0) || !(b < 0)) return false;  // inside, or moving away
  const double disc = b * b - c;
  if (!(disc >= 0)) return false;
  const double root = -b - std::sqrt(disc);
  if (!(root > 0 && root < tmax)) return false;
  t = float(root);
  return true;
}

}  // namespace rdv
