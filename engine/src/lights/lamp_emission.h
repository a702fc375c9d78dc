// A lamp's node tree, as the add-on lowers it (the light key "emission": its Emission's
// "color" and "strength", docs/scene-format.md). Cycles multiplies both into the lamp's colour
// and evaluates them like a surface's shader whose normal is the direction the light leaves
// by (a point or spot lamp) or the lamp's axis (sun, area), and whose object space is the
// lamp's. So an IES Texture, or any graph of Texture Coordinate > Normal, shapes the lamp's
// emission by direction; everything else in such a tree (Blackbody, Wavelength, Math on
// numbers) is the same in every direction and is evaluated once.
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
  // Parses "emission" for a lamp placed by lamp_to_world. Returns the graph when it varies
  // with the direction and `per_direction` is true; otherwise null, with the tree's value
  // along lamp_to_world's -Z (the axis) in `constant`. Malformed input throws (fail()).
  static std::unique_ptr<LampEmission> parse(const nlohmann::json &j, const Transform &lamp_to_world,
                                             bool per_direction, const std::string &what,
                                             std::vector<std::string> &warnings, Color &constant);
  // The tree's colour x strength along a unit world direction leaving the lamp.
  Color eval(Vec3 dir) const;
  // Its mean luminance over the sphere of directions (the lamp's share of light samples).
  float mean_luminance() const { return mean_; }

 private:
  Color eval_unclamped(Vec3 dir) const;
  TextureGraph graph_;
  int color_ = -1, strength_ = -1;
  ShadingPoint at_lamp_;  // the lamp's position and transform; eval sets the normal
  float mean_ = 1;
};

}  // namespace rdv
