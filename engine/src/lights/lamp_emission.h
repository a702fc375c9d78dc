// A lamp's node tree, as the add-on lowers it (the light key "emission": its Emission's
// "color" and "strength", docs/scene-format.md). Cycles multiplies both into the lamp's colour
// and evaluates them like a surface's shader at the point light leaves the lamp from, whose
// normal is the direction the light leaves by (a point or spot lamp) or the lamp's axis (sun,
// area), and whose object space is the lamp's. So an IES Texture, or any graph of Texture
// Coordinate > Normal, shapes the lamp's emission by direction; a Light Falloff by the
// distance to the point lit (Cycles' ray length); a texture of the point's position (an image
// over an area lamp through Geometry > Parametric) by where on the lamp the light leaves;
// everything else in such a tree (Blackbody, Wavelength, Math on numbers) is the same
// everywhere and is evaluated once.
//
// Cycles 3.4's lamp has no object: Position, Texture Coordinate > Object and Generated are the
// point in world space, UV is 0; Parametric is (1 - u - v, u, 0) of the lamp's own (u, v): over
// an area lamp (0.5 + x, 0.5 + y) with x, y from -0.5 to 0.5 along its X and Y axes, on a point
// or spot lamp the spherical map of the direction light leaves by.
#pragma once
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>
#include "core/math.h"
#include "textures/texture_graph.h"

namespace rdv {

struct Light;  // lights/light.h

class LampEmission {
 public:
  // How the lamp's shader sees it: a point or spot lamp's normal is the direction light
  // leaves by, a sun's and an area lamp's the axis; a sun's light travels an infinite length.
  enum class Shape { Point, Area, Sun };
  // Parses "emission" for `lamp` (its type, position and size set) placed by lamp_to_world.
  // Returns the graph when it varies with the direction (a point or spot lamp), with the
  // distance to the point lit (not a sun) or over the lamp (not a sun); otherwise null, with
  // the tree's value at the lamp's centre along its axis in `constant` (which must be finite
  // and not negative). Image nodes naming a "buffer" find it in `images` (null: none).
  // Malformed input throws (fail()).
  static std::unique_ptr<LampEmission> parse(const nlohmann::json &j, const Transform &lamp_to_world,
                                             const Light &lamp, const ImageBuffers *images, const std::string &what,
                                             std::vector<std::string> &warnings, Color &constant);
  // The tree's colour x strength at point p of the lamp, along a unit world direction leaving
  // it, toward a point `distance` away.
  Color eval(Vec3 p, Vec3 dir, float distance) const;
  // Whether it depends on that distance (Light Falloff): light subpaths weigh their first
  // segment once it is traced (bdpt/subpaths.cpp).
  bool depends_on_distance() const { return by_distance_; }
  // Its mean luminance over the lamp's sphere of directions (a point or spot lamp) or its
  // area (an area lamp) at distance 1 (the lamp's share of light samples).
  float mean_luminance() const { return mean_; }

 private:
  Color eval_unclamped(Vec3 p, Vec3 dir, float distance) const;
  // unphysical: set when some value is negative or not finite (eval emits nothing there).
  float mean_over_lamp(const Light &lamp, bool &unphysical) const;
  TextureGraph graph_;
  int color_ = -1, strength_ = -1;
  ShadingPoint at_lamp_;  // the lamp's transform; eval sets the point and the normal
  Shape shape_ = Shape::Point;
  bool per_direction_ = true, per_point_ = false, by_distance_ = false;
  // An area lamp's centre and axes over their squared lengths: its (x, y) of a point.
  Vec3 centre_{0.0f}, u_axis_{0.0f}, v_axis_{0.0f};
  float mean_ = 1;
};

}  // namespace rdv
