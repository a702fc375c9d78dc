#include "lights/lamp_emission.h"
#include "core/error.h"

namespace rdv {

std::unique_ptr<LampEmission> LampEmission::parse(const nlohmann::json &j, const Transform &lamp_to_world, Shape shape,
                                                  const std::string &what, std::vector<std::string> &warnings,
                                                  Color &constant) {
  if (!j.is_object()) fail(what + ": 'emission' must be an object with 'color' and 'strength'");
  auto e = std::make_unique<LampEmission>();
  for (auto it = j.begin(); it != j.end(); ++it) {
    if (it.key() != "color" && it.key() != "strength")
      fail(what + ": 'emission' has an unknown key '" + it.key() + "'", RDV_ERROR_UNKNOWN_PARAMETER);
    const int node = e->graph_.parse(it.value(), what + " emission '" + it.key() + "'", warnings);
    (it.key() == "color" ? e->color_ : e->strength_) = node;
  }
  // Cycles' shader point on a lamp: at the lamp, its object space the lamp's (Texture
  // Coordinate > Normal is the direction through the transposed lamp-to-world, as Cycles').
  ShadingPoint &sp = e->at_lamp_;
  sp.p = lamp_to_world.column(3);
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) sp.object_to_world[4 * r + c] = lamp_to_world.m[r][c];
  sp.has_object_to_world = true;
  auto any_input = [&](bool (TextureGraph::*depends)(int) const) {
    return (e->color_ >= 0 && (e->graph_.*depends)(e->color_)) ||
           (e->strength_ >= 0 && (e->graph_.*depends)(e->strength_));
  };
  e->per_direction_ = shape == Shape::Point;
  e->by_distance_ = shape != Shape::Sun && any_input(&TextureGraph::depends_on_ray_length);
  const bool varies = (e->per_direction_ && any_input(&TextureGraph::depends_on_normal)) || e->by_distance_;
  auto finite_and_positive = [&](Color v) {
    if (!is_finite(v) || v.x < 0 || v.y < 0 || v.z < 0)
      fail(what + ": its emission must be finite and not negative (along the lamp's axis)");
  };
  const Vec3 axis = -normalize(lamp_to_world.column(2));
  e->at_lamp_.ns = e->at_lamp_.ng = axis;
  constant = e->eval_unclamped(axis, shape == Shape::Sun ? kInf : 1.0f);
  finite_and_positive(constant);
  if (!varies) return nullptr;
  // The mean over the sphere: the midpoints of 64 x 32 cells of equal solid angle.
  constexpr int kPhi = 64, kCos = 32;
  double sum = 0;
  for (int i = 0; i < kCos; ++i) {
    const float z = 1.0f - 2.0f * (float(i) + 0.5f) / kCos, r = safe_sqrt(1.0f - z * z);
    for (int k = 0; k < kPhi; ++k) {
      const float phi = 2.0f * kPi * (float(k) + 0.5f) / kPhi;
      const Color v = e->eval({r * std::cos(phi), r * std::sin(phi), z}, 1.0f);
      if (!is_finite(v)) fail(what + ": its emission is not finite in some directions");
      sum += double(luminance(vmax(v, Color(0.0f))));
    }
  }
  e->mean_ = float(sum / (kPhi * kCos));
  return e;
}

Color LampEmission::eval(Vec3 dir, float distance) const {
  const Color out = eval_unclamped(dir, distance);
  return is_finite(out) ? vmax(out, Color(0.0f)) : Color(0.0f);  // no negative light
}

Color LampEmission::eval_unclamped(Vec3 dir, float distance) const {
  ShadingPoint sp = at_lamp_;
  if (per_direction_) sp.ns = sp.ng = dir;
  sp.ray_length = distance;
  Color out(1.0f);
  if (color_ >= 0) out = graph_.eval(color_, sp);
  if (strength_ >= 0) out = out * graph_.eval(strength_, sp);
  return out;
}

}  // namespace rdv
