#include "textures/voronoi.h"
#include <cmath>
#include "textures/hash.h"

namespace rdv {

namespace {

// A point of D coordinates (x, y, z, w).
template <int D>
struct Point {
  float v[D];
  Point operator+(const Point &o) const { Point r; for (int i = 0; i < D; ++i) r.v[i] = v[i] + o.v[i]; return r; }
  Point operator-(const Point &o) const { Point r; for (int i = 0; i < D; ++i) r.v[i] = v[i] - o.v[i]; return r; }
  Point operator*(float k) const { Point r; for (int i = 0; i < D; ++i) r.v[i] = v[i] * k; return r; }
  Point operator/(float k) const { Point r; for (int i = 0; i < D; ++i) r.v[i] = v[i] / k; return r; }
};

template <int D>
Point<D> splat(float s) { Point<D> r; for (int i = 0; i < D; ++i) r.v[i] = s; return r; }

template <int D>
float dot(const Point<D> &a, const Point<D> &b) {
  float s = a.v[0] * b.v[0];
  for (int i = 1; i < D; ++i) s += a.v[i] * b.v[i];
  return s;
}

template <int D>
Point<D> mix(const Point<D> &a, const Point<D> &b, float t) { return a + (b - a) * t; }
Color mix(Color a, Color b, float t) { return a + (b - a) * t; }
float mix(float a, float b, float t) { return a + t * (b - a); }

// The cell's feature point within it, in [0, 1]^D before the randomness scales it.
Point<1> cell_jitter(const Point<1> &c) { return {{hash::to_float(c.v[0])}}; }
Point<2> cell_jitter(const Point<2> &c) {
  return {{hash::to_float(c.v[0], c.v[1]), hash::to_float(c.v[0], c.v[1], 1.0f)}};
}
Point<3> cell_jitter(const Point<3> &c) {
  const Color h = hash::float3_to_color(c.v[0], c.v[1], c.v[2]);
  return {{h.x, h.y, h.z}};
}
Point<4> cell_jitter(const Point<4> &c) {
  const float x = c.v[0], y = c.v[1], z = c.v[2], w = c.v[3];
  return {{hash::to_float(x, y, z, w), hash::to_float(w, x, y, z), hash::to_float(z, w, x, y),
           hash::to_float(y, z, w, x)}};
}
Color cell_color(const Point<1> &c) { return hash::float1_to_color(c.v[0]); }
Color cell_color(const Point<2> &c) { return hash::float2_to_color(c.v[0], c.v[1]); }
Color cell_color(const Point<3> &c) { return hash::float3_to_color(c.v[0], c.v[1], c.v[2]); }
Color cell_color(const Point<4> &c) { return hash::float4_to_color(c.v[0], c.v[1], c.v[2], c.v[3]); }

template <int D>
float distance(const Point<D> &a, const Point<D> &b, VoronoiMetric metric, float exponent) {
  if (D == 1) return std::fabs(b.v[0] - a.v[0]);  // every metric, as Blender
  const Point<D> d = a - b;
  switch (metric) {
    case VoronoiMetric::Euclidean: return std::sqrt(dot(d, d));
    case VoronoiMetric::Manhattan: {
      float s = std::fabs(d.v[0]);
      for (int i = 1; i < D; ++i) s += std::fabs(d.v[i]);
      return s;
    }
    case VoronoiMetric::Chebychev: {
      float s = std::fabs(d.v[D - 1]);
      for (int i = D - 2; i >= 0; --i) s = std::max(std::fabs(d.v[i]), s);
      return s;
    }
    case VoronoiMetric::Minkowski: {
      float s = std::pow(std::fabs(d.v[0]), exponent);
      for (int i = 1; i < D; ++i) s += std::pow(std::fabs(d.v[i]), exponent);
      return std::pow(s, 1.0f / exponent);
    }
  }
  return 0.0f;
}

// The cells around the point's cell, x fastest then y, z and w, as Blender's loops visit
// them (the order matters to Smooth F1's running blend and to ties).
template <int D>
struct CellOffsets {
  int radius;
  int count() const { int n = 1; for (int i = 0; i < D; ++i) n *= 2 * radius + 1; return n; }
  Point<D> operator[](int n) const {
    Point<D> o;
    for (int i = 0; i < D; ++i, n /= 2 * radius + 1) o.v[i] = float(n % (2 * radius + 1) - radius);
    return o;
  }
};

template <int D>
struct Cell {
  Point<D> position, local;  // the point's cell (its lowest corner) and the point within it
  explicit Cell(const Point<D> &p) {
    for (int i = 0; i < D; ++i) position.v[i] = std::floor(p.v[i]);
    local = p - position;
  }
  // The feature point of the cell at offset o, relative to this cell.
  Point<D> feature(const Point<D> &o, float randomness) const { return o + cell_jitter(position + o) * randomness; }
};

template <int D>
struct Feature {
  float distance = 8;
  Color color{0.0f};
  Point<D> position = splat<D>(0.0f);
};

template <int D>
Feature<D> f1(const Cell<D> &cell, const VoronoiParams &v) {
  float best = 8;
  Point<D> best_offset = splat<D>(0.0f), best_point = splat<D>(0.0f);
  const CellOffsets<D> around{1};
  for (int n = 0; n < around.count(); ++n) {
    const Point<D> o = around[n], point = cell.feature(o, v.randomness);
    const float d = distance(point, cell.local, v.metric, v.exponent);
    if (d < best) best = d, best_offset = o, best_point = point;
  }
  return {best, cell_color(cell.position + best_offset), best_point + cell.position};
}

template <int D>
Feature<D> f2(const Cell<D> &cell, const VoronoiParams &v) {
  float d1 = 8, d2 = 8;
  Point<D> offset1 = splat<D>(0.0f), point1 = splat<D>(0.0f), offset2 = splat<D>(0.0f), point2 = splat<D>(0.0f);
  const CellOffsets<D> around{1};
  for (int n = 0; n < around.count(); ++n) {
    const Point<D> o = around[n], point = cell.feature(o, v.randomness);
    const float d = distance(point, cell.local, v.metric, v.exponent);
    if (d < d1) {
      d2 = d1, offset2 = offset1, point2 = point1;
      d1 = d, offset1 = o, point1 = point;
    } else if (d < d2) {
      d2 = d, offset2 = o, point2 = point;
    }
  }
  return {d2, cell_color(cell.position + offset2), point2 + cell.position};
}

// Smooth F1: a running smooth minimum over the 5^D cells around (Inigo Quilez's), blending
// colour and position by the same weights.
template <int D>
Feature<D> smooth_f1(const Cell<D> &cell, const VoronoiParams &v, float smoothness) {
  float smooth_distance = 8;
  Color smooth_color(0.0f);
  Point<D> smooth_position = splat<D>(0.0f);
  const CellOffsets<D> around{2};
  for (int n = 0; n < around.count(); ++n) {
    const Point<D> o = around[n], point = cell.feature(o, v.randomness);
    const float d = distance(point, cell.local, v.metric, v.exponent);
    const float h = smoothstep(0.0f, 1.0f, 0.5f + 0.5f * (smooth_distance - d) / smoothness);
    float correction = smoothness * h * (1.0f - h);
    smooth_distance = mix(smooth_distance, d, h) - correction;
    correction /= 1.0f + 3.0f * smoothness;
    smooth_color = mix(smooth_color, cell_color(cell.position + o), h) - Color(correction);
    smooth_position = mix(smooth_position, point, h) - splat<D>(correction);
  }
  return {smooth_distance, smooth_color, cell.position + smooth_position};
}

// Distance to the nearest cell edge: to the bisecting planes between the closest point and
// each other point (always Euclidean, as Blender).
template <int D>
float distance_to_edge(const Cell<D> &cell, float randomness) {
  const CellOffsets<D> around{1};
  Point<D> to_closest = splat<D>(0.0f);
  float best = 8;
  for (int n = 0; n < around.count(); ++n) {
    const Point<D> to_point = cell.feature(around[n], randomness) - cell.local;
    const float d = dot(to_point, to_point);
    if (d < best) best = d, to_closest = to_point;
  }
  best = 8;
  for (int n = 0; n < around.count(); ++n) {
    const Point<D> to_point = cell.feature(around[n], randomness) - cell.local;
    const Point<D> perpendicular = to_point - to_closest;
    const float len2 = dot(perpendicular, perpendicular);
    if (len2 > 0.0001f) best = std::min(best, dot((to_closest + to_point) / 2.0f, perpendicular / std::sqrt(len2)));
  }
  return best;
}

float distance_to_edge(const Cell<1> &cell, float randomness) {
  const float c = cell.position.v[0], local = cell.local.v[0];
  const float mid = hash::to_float(c) * randomness;
  const float left = -1.0f + hash::to_float(c - 1.0f) * randomness;
  const float right = 1.0f + hash::to_float(c + 1.0f) * randomness;
  return std::min(std::fabs((mid + left) / 2.0f - local), std::fabs((mid + right) / 2.0f - local));
}

// Half the distance from the closest point to its own closest neighbour.
template <int D>
float n_sphere_radius(const Cell<D> &cell, float randomness) {
  const CellOffsets<D> around{1};
  Point<D> closest = splat<D>(0.0f), closest_offset = splat<D>(0.0f);
  float best = 8;
  for (int n = 0; n < around.count(); ++n) {
    const Point<D> point = cell.feature(around[n], randomness);
    const Point<D> d = point - cell.local;
    const float len = std::sqrt(dot(d, d));
    if (len < best) best = len, closest = point, closest_offset = around[n];
  }
  best = 8;
  Point<D> neighbour = splat<D>(0.0f);
  for (int n = 0; n < around.count(); ++n) {
    if (n == around.count() / 2) continue;  // the centre: the closest point's own cell
    const Point<D> point = cell.feature(around[n] + closest_offset, randomness);
    const Point<D> d = closest - point;
    const float len = std::sqrt(dot(d, d));
    if (len < best) best = len, neighbour = point;
  }
  const Point<D> d = neighbour - closest;
  return std::sqrt(dot(d, d)) / 2.0f;
}

template <int D>
VoronoiResult evaluate(const Point<D> &p, const VoronoiParams &v) {
  const Cell<D> cell(p);
  VoronoiResult r;
  Feature<D> f;
  switch (v.feature) {
    case VoronoiFeature::F1: f = f1(cell, v); break;
    case VoronoiFeature::F2: f = f2(cell, v); break;
    case VoronoiFeature::SmoothF1: f = smooth_f1(cell, v, clampf(v.smoothness / 2.0f, 0.0f, 0.5f)); break;
    case VoronoiFeature::DistanceToEdge: r.distance = distance_to_edge(cell, v.randomness); return r;
    case VoronoiFeature::NSphereRadius: r.radius = n_sphere_radius(cell, v.randomness); return r;
  }
  r.distance = f.distance;
  r.color = f.color;
  // Position and W back in the input's units (0 at Scale 0, as Blender).
  const Point<D> at = v.scale != 0.0f ? f.position / v.scale : splat<D>(0.0f);
  auto coord = [&](int i) { return i < D ? at.v[i] : 0.0f; };
  if (D == 1) r.w = coord(0);
  else r.position = Vec3(coord(0), coord(1), D >= 3 ? coord(2) : 0.0f);
  if (D == 4) r.w = coord(3);
  return r;
}

}  // namespace

VoronoiResult voronoi_texture(Vec3 p, float w, int dims, VoronoiParams v) {
  v.randomness = clampf(v.randomness, 0.0f, 1.0f);
  p = p * v.scale;
  w *= v.scale;
  VoronoiResult r;
  switch (dims) {
    case 1: r = evaluate(Point<1>{{w}}, v); break;
    case 2: r = evaluate(Point<2>{{p.x, p.y}}, v); break;
    case 4: r = evaluate(Point<4>{{p.x, p.y, p.z, w}}, v); break;
    default: r = evaluate(Point<3>{{p.x, p.y, p.z}}, v); break;
  }
  // A huge or non-finite input (a scale of 1e30) has no cells: nothing but finite values out.
  auto finite = [](float x) { return std::isfinite(x) ? x : 0.0f; };
  r.distance = finite(r.distance), r.w = finite(r.w), r.radius = finite(r.radius);
  r.color = {finite(r.color.x), finite(r.color.y), finite(r.color.z)};
  r.position = {finite(r.position.x), finite(r.position.y), finite(r.position.z)};
  return r;
}

}  // namespace rdv
