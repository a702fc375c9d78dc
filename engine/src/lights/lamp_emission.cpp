#include "lights/lamp_emission.h"
#include "core/error.h"
#include "lights/light.h"

namespace rdv {

namespace {
// Cycles' map_to_sphere (util/math.h): a point or spot lamp's (u, v) of the direction light
// leaves by.
Vec2 map_to_sphere(Vec3 d) {
  const float l = length(d);
  if (!(l > 0)) return {0.0f, 0.0f};
  const float u = d.x == 0 && d.y == 0 ? 0.0f : 0.5f - std::atan2(d.x, d.y) / (2 * kPi);
  return {u, 1.0f - std::acos(clampf(d.z / l, -1.0f, 1.0f)) / kPi};
}
}  // namespace

std::unique_ptr<LampEmission> LampEmission::parse(const nlohmann::json &j, const Transform &lamp_to_world,
                                                  const Light &lamp, const ImageBuffers *images,
                                                  const std::string &what, std::vector<std::string> &warnings,
                                                  Color &constant) {
  if (!j.is_object()) fail(what + ": 'emission' must be an object with 'color' and 'strength'");
  auto e = std::make_unique<LampEmission>();
  e->graph_.image_buffers = images;
  for (auto it = j.begin(); it != j.end(); ++it) {
    if (it.key() != "color" && it.key() != "strength")
      fail(what + ": 'emission' has an unknown key '" + it.key() + "'", RDV_ERROR_UNKNOWN_PARAMETER);
    const int node = e->graph_.parse(it.value(), what + " emission '" + it.key() + "'", warnings);
    (it.key() == "color" ? e->color_ : e->strength_) = node;
  }
  e->graph_.image_buffers = nullptr;  // only while parsing: the scene's buffers may change later
  // Cycles' shader point on a lamp: its object space the lamp's (Texture Coordinate > Normal
  // is the direction through the transposed lamp-to-world, as Cycles').
  ShadingPoint &sp = e->at_lamp_;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) sp.object_to_world[4 * r + c] = lamp_to_world.m[r][c];
  sp.has_object_to_world = true;
  auto any_input = [&](bool (TextureGraph::*depends)(int) const) {
    return (e->color_ >= 0 && (e->graph_.*depends)(e->color_)) ||
           (e->strength_ >= 0 && (e->graph_.*depends)(e->strength_));
  };
  e->shape_ = lamp.type == LightType::Point || lamp.type == LightType::Spot ? Shape::Point
              : lamp.type == LightType::Sun                                 ? Shape::Sun
                                                                            : Shape::Area;
  // A sun's shader point is its direction (Cycles 3.4's P of a distant light): the tree there.
  const bool sun = e->shape_ == Shape::Sun;
  e->per_direction_ = e->shape_ == Shape::Point;
  const bool reads_point = any_input(&TextureGraph::depends_on_point);
  e->per_point_ = reads_point;  // for the value below (a sun's at its direction); then as it varies
  e->by_distance_ = !sun && any_input(&TextureGraph::depends_on_ray_length);
  const bool varies = (e->per_direction_ && any_input(&TextureGraph::depends_on_normal)) || (reads_point && !sun) ||
                      e->by_distance_;
  e->centre_ = lamp.position;
  if (e->shape_ == Shape::Area) {
    e->u_axis_ = lamp.edge_u / length_squared(lamp.edge_u);
    e->v_axis_ = lamp.edge_v / length_squared(lamp.edge_v);
  }
  sp.ns = sp.ng = lamp.axis;
  constant = e->eval_unclamped(sun ? lamp.axis : lamp.position, lamp.axis, sun ? kInf : 1.0f);
  e->per_point_ = reads_point && !sun;
  if (!varies) {
    if (!is_finite(constant) || constant.x < 0 || constant.y < 0 || constant.z < 0)
      fail(what + ": its emission must be finite and not negative (along the lamp's axis)");
    return nullptr;
  }
  // What varies emits nothing where it is negative or not finite (eval): said once.
  bool unphysical = false;
  e->mean_ = e->mean_over_lamp(lamp, unphysical);
  if (unphysical)
    warnings.push_back(what + ": its emission is negative or not finite at some points or in some directions; "
                              "no light there");
  return e;
}

float LampEmission::mean_over_lamp(const Light &lamp, bool &unphysical) const {
  double sum = 0;
  int n = 0;
  auto add = [&](Vec3 p, Vec3 dir) {
    const Color v = eval_unclamped(p, dir, 1.0f);
    const bool finite = is_finite(v);
    if (!finite || v.x < 0 || v.y < 0 || v.z < 0) unphysical = true;
    sum += finite ? double(luminance(vmax(v, Color(0.0f)))) : 0.0;  // as eval clamps it, without a second evaluation
    ++n;
  };
  if (shape_ == Shape::Point) {
    // The midpoints of 64 x 32 cells of equal solid angle, each from the point of the lamp's
    // sphere that faces it.
    constexpr int kPhi = 64, kCos = 32;
    for (int i = 0; i < kCos; ++i) {
      const float z = 1.0f - 2.0f * (float(i) + 0.5f) / kCos, r = safe_sqrt(1.0f - z * z);
      for (int k = 0; k < kPhi; ++k) {
        const float phi = 2.0f * kPi * (float(k) + 0.5f) / kPhi;
        const Vec3 dir(r * std::cos(phi), r * std::sin(phi), z);
        add(lamp.position + dir * lamp.radius, dir);
      }
    }
  } else {
    // The midpoints of 64 x 64 cells over the rectangle (those inside an ellipse), along the
    // axis: an area lamp's tree sees only its axis as the normal.
    constexpr int kCells = 64;
    for (int i = 0; i < kCells; ++i)
      for (int k = 0; k < kCells; ++k) {
        const float x = (float(i) + 0.5f) / kCells - 0.5f, y = (float(k) + 0.5f) / kCells - 0.5f;
        if (lamp.ellipse && x * x + y * y > 0.25f) continue;
        add(lamp.position + lamp.edge_u * x + lamp.edge_v * y, lamp.axis);
      }
  }
  return n > 0 ? float(sum / n) : 0.0f;
}

Color LampEmission::eval(Vec3 p, Vec3 dir, float distance) const {
  const Color out = eval_unclamped(p, dir, distance);
  return is_finite(out) ? vmax(out, Color(0.0f)) : Color(0.0f);  // no negative light
}

Color LampEmission::eval_unclamped(Vec3 p, Vec3 dir, float distance) const {
  ShadingPoint sp = at_lamp_;
  if (per_direction_) sp.ns = sp.ng = dir;
  if (per_point_) {  // (only a tree that reads them: an IES lamp's evaluation skips this)
    // Cycles' lamp has no object: its object and generated coordinates are world positions.
    sp.p = sp.p_object = sp.generated = p;
    Vec2 uv;  // Cycles' (u, v) on the lamp, in Embree's barycentric notation
    if (shape_ == Shape::Area) {
      const Vec3 q = p - centre_;
      const float x = dot(q, u_axis_), y = dot(q, v_axis_);
      uv = {y + 0.5f, -x - y};
    } else {
      uv = map_to_sphere(dir);
    }
    sp.b[0] = 1.0f - uv.x - uv.y;
    sp.b[1] = uv.x;
    sp.b[2] = uv.y;
  }
  sp.ray_length = distance;
  Color out(1.0f);
  if (color_ >= 0) out = graph_.eval(color_, sp);
  if (strength_ >= 0) out = out * graph_.eval(strength_, sp);
  return out;
}

}  // namespace rdv
