// World background from an equirectangular HDRI (Blender's Environment Texture in
// equirectangular projection, optionally rotated by a Mapping node), importance
// sampled: a piecewise-constant 2D distribution over the image's pixels weighted by
// luminance x sin(theta) (the solid angle a pixel row covers), sampled by rows then
// columns. Radiance is looked up bilinearly (Blender's default Linear interpolation);
// the sampling pdf is positive wherever a pixel or its neighbours are non-zero.
//
// Blender's mapping: direction d (after rotation) -> u = 0.5 - atan2(d.y, d.x) / 2pi,
// v = 1 - acos(d.z) / pi (v = 1 at the zenith, the image's top row).
#pragma once
#include <memory>
#include <string>
#include <vector>
#include "core/distribution.h"
#include "core/math.h"

namespace rdv {

class EnvironmentMap {
 public:
  // Loads `path` (any OIIO format; converted to scene-linear from `colorspace`, "" =
  // Linear for float files, sRGB otherwise). rotation: XYZ Euler radians of the Mapping
  // node (type Point) applied to the lookup direction. Throws (fail) if unreadable.
  static std::shared_ptr<EnvironmentMap> load(const std::string &path, const std::string &colorspace,
                                              Vec3 rotation, Color tint);
  // From pixels in memory (rows from the top, RGB float), for tests.
  EnvironmentMap(int width, int height, std::vector<float> rgb, Vec3 rotation, Color tint);

  Color eval(Vec3 dir_world) const;
  // Direction toward the environment, its radiance and its solid-angle pdf.
  bool sample(Vec2 u, Vec3 &dir_world, Color &L, float &pdf) const;
  float pdf(Vec3 dir_world) const;
  // Mean radiance over the sphere (each pixel weighted by its solid angle).
  Color mean() const { return mean_; }
  int width() const { return w_; }
  int height() const { return h_; }
  size_t memory_bytes() const;

 private:
  Vec3 to_local(Vec3 d) const;   // world -> image space (the Mapping rotation)
  Vec3 to_world(Vec3 d) const;
  Color texel(int x, int y) const;
  int w_, h_;
  std::vector<float> rgb_;
  Vec3 rot_[3];  // rotation matrix rows
  Color tint_;
  Color mean_{0.0f};
  Distribution1D rows_;
  std::vector<Distribution1D> cols_;
};

}  // namespace rdv
