// Blender's camera model: perspective / orthographic, sensor fit, shift, clipping and
// a thin lens with optional polygonal aperture. Cycles' viewplane conventions, so a
// render frames exactly what Blender's camera view shows.
#pragma once
#include "core/math.h"
#include "core/params.h"

namespace rdv {

struct Camera {
  enum class Type { Perspective, Orthographic } type = Type::Perspective;
  Transform to_world;
  // Viewplane at unit distance (perspective) or in scene units (orthographic).
  float left = -1, right = 1, bottom = -1, top = 1;
  float clip_start = 0.1f, clip_end = 1000.0f;
  float aperture_radius = 0;  // scene units; 0 = pinhole
  float focus_distance = 10;
  int blades = 0;
  float blade_rotation = 0;
  // Raw parameters; the viewplane depends on the image aspect (set_resolution).
  float focal_length = 50, sensor_width = 36, sensor_height = 24, shift_x = 0, shift_y = 0, ortho_scale = 6;
  int sensor_fit = 0;  // 0 auto, 1 horizontal, 2 vertical

  static Camera from_params(Params &p);
  void set_resolution(int width, int height);

  // raster: continuous pixel coordinates, (0,0) = top-left corner of the image.
  // u_lens in [0,1)^2. Returns the ray and its valid length.
  Ray generate_ray(Vec2 raster, Vec2 u_lens) const;
  Vec3 position() const { return to_world.column(3); }
  Vec3 forward() const { return normalize(-to_world.column(2)); }

 private:
  int width_ = 1, height_ = 1;
};

}  // namespace rdv
