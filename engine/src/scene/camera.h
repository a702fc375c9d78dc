// Blender's camera model: perspective / orthographic, sensor fit, shift, clipping and
// a thin lens with optional polygonal aperture. Cycles' viewplane conventions, so a
// render frames exactly what Blender's camera view shows.
#pragma once
#include <vector>
#include "core/math.h"
#include "core/params.h"
#include "core/ray_cone.h"

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

  // Motion blur (scene/motion.h): the shutter opens and closes at these times (frames,
  // relative to the frame rendered; equal: no motion blur), and a moving camera's
  // to_world at n >= 2 evenly spaced times between them (empty: it does not move).
  float shutter_open = 0, shutter_close = 0;
  std::vector<Transform> motion;
  bool shutter_is_open() const { return shutter_close > shutter_open; }
  bool moves() const { return shutter_is_open() && motion.size() >= 2; }
  // Places the camera at to_world (a moving camera at a sample's time; Scene::camera_now):
  // a blended rotation is made orthogonal again, keeping its axes' lengths.
  void move_to(const Transform &to_world);

  static Camera from_params(Params &p);
  void set_resolution(int width, int height);

  // raster: continuous pixel coordinates, (0,0) = top-left corner of the image.
  // u_lens in [0,1)^2. Returns the ray (starting at the near clip plane) and its valid
  // length; lens_point receives the point on the lens the ray comes from, cone the
  // ray's footprint (one pixel wide; core/ray_cone.h).
  Ray generate_ray(Vec2 raster, Vec2 u_lens, Vec3 *lens_point = nullptr, RayCone *cone = nullptr) const;
  // The same ray from a given point of the aperture (`lens`: its offset from the lens centre
  // in camera space, as lens_sample makes it; ignored by a pinhole).
  Ray generate_ray_from_lens(Vec2 raster, Vec2 lens) const;
  // A point of the aperture, uniform over it (disk or polygon), as its camera-space offset
  // and in the world; and the offset of a world point on the aperture's plane.
  Vec2 lens_sample(Vec2 u) const;
  Vec3 lens_to_world(Vec2 lens) const { return to_world.point(Vec3(lens.x, lens.y, 0)); }
  Vec2 lens_of_point(Vec3 p) const;
  // Orthographic cameras: a raster point's foot on the image plane (camera space x, y), and back.
  Vec2 plane_of_raster(Vec2 raster) const;
  Vec2 raster_of_plane(Vec2 plane) const;
  // The aperture's true area (pi r^2, or the polygon's); 1 for a pinhole. lens_area() is
  // pi r^2 for every aperture: BDPT's strategies use it on both sides, where it cancels.
  float aperture_area() const;

  // ---- Importance, for light tracing and BDPT's t = 1 strategies (pbrt's We) ----
  // Only perspective cameras (pinhole or thin lens) can be reached by light paths;
  // an orthographic camera's directions are a delta.
  bool can_be_connected() const { return type == Type::Perspective; }
  float lens_area() const { return aperture_radius > 0 ? kPi * aperture_radius * aperture_radius : 1.0f; }
  // Importance of a ray leaving the lens at ray.o along ray.d; raster receives where it
  // lands. Zero outside the image.
  float importance(const Ray &ray, Vec2 *raster) const;
  void importance_pdf(const Ray &ray, float &pdf_pos, float &pdf_dir) const;
  struct ImportanceSample {
    Vec3 lens_point, wi;  // wi: from the reference point toward the lens
    float dist = 0, pdf = 0, We = 0;
    float pdf_dir = 0;  // density of the camera sending a ray from lens_point to ref (solid angle)
    Vec2 raster;
  };
  // A point on the lens seen from ref, with its solid-angle pdf at ref.
  bool sample_importance(Vec3 ref, Vec2 u_lens, ImportanceSample &out) const;
  // Perspective cameras: where a ray from the pinhole along unit d lands on the image
  // (raster, not limited to the image) and its cosine to the view axis; false behind.
  bool raster_of_direction(Vec3 d, Vec2 &raster, float &cos_theta) const;
  // Perspective cameras with a thin lens: where the ray from lens_point (on the aperture)
  // along unit d lands on the image (through its point on the focal plane); a pinhole:
  // raster_of_direction. Orthographic cameras with depth of field: lens_point is on the
  // image plane, the raster point the foot of the ray's point on the focal plane, and false
  // unless lens_point is on the aperture around that foot (as generate_ray makes its rays).
  bool raster_through_lens(Vec3 lens_point, Vec3 d, Vec2 &raster, float &cos_theta) const;
  // Whether a camera-space offset lies on the aperture (disk or polygon, as lens_sample).
  bool aperture_covers(Vec2 offset) const;
  // Orthographic cameras: the raster position of the world point p (not limited to the
  // image) and its foot on the image plane (where its camera ray starts); false behind.
  bool raster_of_point(Vec3 p, Vec2 &raster, Vec3 &plane_point) const;
  // The orthographic image's area on its plane, in scene units squared.
  float image_plane_area() const;
  // The image's area on the viewplane at unit distance (perspective).
  float viewplane_area() const { return (right - left) * (top - bottom); }
  Vec3 position() const { return to_world.column(3); }
  Vec3 forward() const { return forward_; }

 private:
  Ray ray_from(Vec2 raster, const Vec2 *lens, Vec3 *lens_point, RayCone *cone) const;
  int width_ = 1, height_ = 1;
  Transform to_camera_;
  Vec3 forward_{0, 0, -1};
};

}  // namespace rdv
