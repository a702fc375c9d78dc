// A lamp's node tree, as the add-on lowers it (the light key "emission": its Emission's
// "color" and "strength", docs/scene-format.md). Cycles multiplies both into the lamp's colour
// and evaluates them like a surface's shader whose normal is the direction the light leaves
// by (a point or spot lamp) or the lamp's axis (sun, area), and whose object space is the
// lamp's. So an IES Texture, or any graph of Texture Coordinate > Normal, shapes the lamp's
// emission by direction; a Light Falloff by the distance to the point lit (Cycles' ray
// length); everything else in such a tree (Blackbody, Wavelength, Math on numbers) is the same
// in every direction and is evaluated once.
#pragma once
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>
#include "core/math.h"
#include "textures/texture_graph.h"

namespace rdv {

class LampEmission {
 public:
  // How the lamp's shader sees it: a point or spot lamp's normal is the direction light
  // leaves by, a sun's and an area lamp's the axis; a sun's light travels an infinite length.
  enum class Shape { Point, Area, Sun };
  // Parses "emission" for a lamp placed by lamp_to_world. Returns the graph when it varies
  // with the direction (a point or spot lamp) or with the distance to the point lit (not a
  // sun); otherwise null, with the tree's value along lamp_to_world's -Z (the axis) in
  // `constant`. Malformed input throws (fail()).
  static std::unique_ptr<LampEmission> parse(const nlohmann::json &j, const Transform &lamp_to_world, Shape shape,
                                             const std::string &what, std::vector<std::string> &warnings,
                                             Color &constant);
  // The tree's colour x strength along a unit world direction leaving the lamp, toward a
  // point `distance` away.
  Color eval(Vec3 dir, float distance) const;
  // Whether it depends on that distance (Light Falloff): light subpaths weigh their first
  // segment once it is traced (bdpt/subpaths.cpp).
  bool depends_on_distance() const { return by_distance_; }
  // Its mean luminance over the sphere of directions at distance 1 (the lamp's share of
  // light samples).
  float mean_luminance() const { return mean_; }

 private:
  Color eval_unclamped(Vec3 dir, float distance) const;
  TextureGraph graph_;
  int color_ = -1, strength_ = -1;
  ShadingPoint at_lamp_;  // the lamp's position and transform; eval sets the normal
  bool per_direction_ = true, by_distance_ = false;
  float mean_ = 1;
};

}  // namespace rdv
