#include "scene/camera.h"
#include "core/sampling.h"
#include <cmath>
#include <nlohmann/json.hpp>

namespace rdv {

Camera Camera::from_params(Params &p) {
  Camera c;
  std::string type = p.get_string("type", "perspective");
  if (type == "perspective") c.type = Type::Perspective;
  else if (type == "orthographic") c.type = Type::Orthographic;
  else fail(p.what() + ": 'type' must be perspective or orthographic, got '" + type + "'");
  c.to_world = p.get_transform("transform", Transform());
  if (std::fabs(c.to_world.det3()) < 1e-20f) fail(p.what() + ": 'transform' is degenerate (zero scale)");
  c.focal_length = p.get_float("focal_length", 50);
  c.sensor_width = p.get_float("sensor_width", 36);
  c.sensor_height = p.get_float("sensor_height", 24);
  std::string fit = p.get_string("sensor_fit", "AUTO");
  if (fit == "AUTO") c.sensor_fit = 0;
  else if (fit == "HORIZONTAL") c.sensor_fit = 1;
  else if (fit == "VERTICAL") c.sensor_fit = 2;
  else fail(p.what() + ": 'sensor_fit' must be AUTO, HORIZONTAL or VERTICAL");
  c.shift_x = p.get_float("shift_x", 0);
  c.shift_y = p.get_float("shift_y", 0);
  c.ortho_scale = p.get_float("ortho_scale", 6);
  c.clip_start = p.get_float("clip_start", 0.1f);
  c.clip_end = p.get_float("clip_end", 1000.0f);
  float fstop = p.get_float("fstop", 0);
  c.aperture_radius = p.get_float("aperture_radius", 0);
  if (fstop > 0) {  // Blender: radius = lens_mm * 1e-3 / (2 fstop) (perspective), 1 / (2 fstop) (ortho)
    c.aperture_radius = c.type == Type::Perspective ? c.focal_length * 1e-3f / (2 * fstop) : 1.0f / (2 * fstop);
  }
  c.focus_distance = p.get_float("focus_distance", 10);
  c.blades = p.get_int("blades", 0);
  c.blade_rotation = p.get_float("blade_rotation", 0);
  if (c.focal_length <= 0 || c.sensor_width <= 0 || c.sensor_height <= 0 || c.ortho_scale <= 0)
    fail(p.what() + ": focal_length, sensor sizes and ortho_scale must be positive");
  if (c.clip_start < 0 || c.clip_end <= c.clip_start) fail(p.what() + ": need 0 <= clip_start < clip_end");
  if (c.aperture_radius < 0 || c.focus_distance <= 0) fail(p.what() + ": aperture must be >= 0 and focus_distance > 0");
  if (c.blades != 0 && c.blades < 3) fail(p.what() + ": 'blades' must be 0 (round) or at least 3");
  c.shutter_open = p.get_float("shutter_open", 0);
  c.shutter_close = p.get_float("shutter_close", 0);
  if (!std::isfinite(c.shutter_open) || !std::isfinite(c.shutter_close) || c.shutter_close < c.shutter_open)
    fail(p.what() + ": the shutter must close ('shutter_close', " + std::to_string(c.shutter_close) +
         ") no earlier than it opens ('shutter_open', " + std::to_string(c.shutter_open) + "): a shutter time >= 0");
  if (const nlohmann::json *steps = p.get_json("motion")) {
    const nlohmann::json &motion = *steps;
    if (!motion.is_array()) fail(p.what() + ": 'motion' must be a list of transforms");
    for (size_t k = 0; k < motion.size(); ++k) {
      Transform t = parse_transform(motion[k], p.what() + " 'motion' step " + std::to_string(k));
      if (!(std::fabs(t.det3()) >= 1e-20f))
        fail(p.what() + ": 'motion' step " + std::to_string(k) + " is degenerate (zero scale)");
      c.motion.push_back(t);
    }
    if (c.motion.size() == 1) c.motion.clear();  // one step: it does not move
  }
  c.to_camera_ = c.to_world.inverse();
  c.forward_ = normalize(-c.to_world.column(2));
  return c;
}

void Camera::move_to(const Transform &t) {
  // Gram-Schmidt on the blended axes: view direction (-z) first, then x, y from them.
  Vec3 x = t.column(0), y = t.column(1), z = t.column(2);
  float lx = length(x), ly = length(y), lz = length(z);
  Vec3 zn = normalize(z);
  Vec3 xn = normalize(x - zn * dot(x, zn));
  Vec3 yn = cross(zn, xn);
  if (dot(yn, y) < 0) yn = -yn;  // a mirrored camera stays mirrored
  to_world = t;
  for (int r = 0; r < 3; ++r) {
    to_world.m[r][0] = xn[r] * lx;
    to_world.m[r][1] = yn[r] * ly;
    to_world.m[r][2] = zn[r] * lz;
  }
  to_camera_ = to_world.inverse();
  forward_ = normalize(-to_world.column(2));
}

void Camera::set_resolution(int width, int height) {
  width_ = width;
  height_ = height;
  // Cycles' blender_camera_viewplane: the fitted sensor dimension spans 2 units of
  // the viewplane's longer side; shift is in units of that fitted dimension.
  float xratio = static_cast<float>(width), yratio = static_cast<float>(height);
  bool horizontal_fit = sensor_fit == 0 ? xratio > yratio : sensor_fit == 1;
  float sensor = sensor_fit == 2 ? sensor_height : sensor_width;
  float aspect = horizontal_fit ? xratio / yratio : yratio / xratio;
  float xaspect = horizontal_fit ? aspect : 1.0f, yaspect = horizontal_fit ? 1.0f : aspect;
  // Scale so that the fitted dimension's half-extent is sensor / (2 f) (perspective)
  // or ortho_scale / 2 (orthographic).
  float half_fitted = type == Type::Perspective ? sensor / (2.0f * focal_length) : ortho_scale * 0.5f;
  float scale = half_fitted / aspect;
  left = -xaspect * scale;
  right = xaspect * scale;
  bottom = -yaspect * scale;
  top = yaspect * scale;
  float dx = 2.0f * aspect * shift_x * scale, dy = 2.0f * aspect * shift_y * scale;
  left += dx; right += dx; bottom += dy; top += dy;
}

Vec2 Camera::lens_sample(Vec2 u) const {
  Vec2 lens = blades >= 3 ? regular_polygon(u, blades, blade_rotation) : concentric_disk(u);
  return lens * aperture_radius;
}

Ray Camera::generate_ray(Vec2 raster, Vec2 u_lens, Vec3 *lens_point, RayCone *cone) const {
  if (aperture_radius > 0) {
    const Vec2 lens = lens_sample(u_lens);
    return ray_from(raster, &lens, lens_point, cone);
  }
  return ray_from(raster, nullptr, lens_point, cone);
}

Ray Camera::generate_ray_from_lens(Vec2 raster, Vec2 lens) const {
  return ray_from(raster, aperture_radius > 0 ? &lens : nullptr, nullptr, nullptr);
}

Vec2 Camera::plane_of_raster(Vec2 raster) const {
  return {left + raster.x / float(width_) * (right - left), top - raster.y / float(height_) * (top - bottom)};
}

Vec2 Camera::raster_of_plane(Vec2 plane) const {
  return {(plane.x - left) / (right - left) * float(width_), (top - plane.y) / (top - bottom) * float(height_)};
}

Ray Camera::ray_from(Vec2 raster, const Vec2 *lens_offset, Vec3 *lens_point, RayCone *cone) const {
  float fx = raster.x / width_, fy = raster.y / height_;
  Vec3 plane{left + fx * (right - left), top - fy * (top - bottom), 0};
  Vec3 o, d;
  if (type == Type::Perspective) {
    o = Vec3(0.0f);
    d = Vec3(plane.x, plane.y, -1.0f);
  } else {
    o = Vec3(plane.x, plane.y, 0.0f);
    d = Vec3(0, 0, -1.0f);
  }
  if (lens_offset) {
    const Vec2 lens = *lens_offset;
    Vec3 focus = o + d * focus_distance;  // d.z == -1: this point lies on the focal plane
    o = o + Vec3(lens.x, lens.y, 0);
    d = focus - o;
  }
  d = normalize(d);
  if (lens_point) *lens_point = to_world.point(o);
  // Clip planes are depths along the camera's -Z axis.
  float inv_depth_per_t = 1.0f / -d.z;
  Ray ray;
  Vec3 o_clip = o + d * (clip_start * inv_depth_per_t);
  ray.o = to_world.point(o_clip);
  Vec3 dw = to_world.vector(d);
  float len = length(dw);
  ray.d = dw / len;
  ray.tmax = (clip_end - clip_start) * inv_depth_per_t * len;
  if (cone) {
    // One pixel of the viewplane: at unit depth (perspective; the apex is the pinhole,
    // the lens is ignored) or in scene units (orthographic), across the ray.
    float pixel = std::max((right - left) / width_, (top - bottom) / height_);
    if (type == Type::Perspective) {
      cone->spread = pixel * -d.z;  // narrower off-axis, where a pixel is seen obliquely
      cone->width = cone->spread * clip_start * inv_depth_per_t * len;
    } else {
      *cone = {pixel * len, 0.0f};
    }
  }
  return ray;
}

// pbrt's PerspectiveCamera::We: importance 1 / (A * lens_area * cos^4) inside the
// image, where A is the image's area on the plane at unit distance.
float Camera::importance(const Ray &ray, Vec2 *raster) const {
  if (type != Type::Perspective) return 0;
  float cos_theta = dot(ray.d, forward_);
  if (cos_theta <= 0) return 0;
  // In camera space, from the lens point's offset and the direction: a world-space
  // point one unit in front of a camera 1e5 from the origin is rounded by 8 mm, more
  // than a pixel's angle (light-tracing splats landed in stripes of columns).
  Vec3 lens = aperture_radius > 0 ? to_camera_.vector(ray.o - position()) : Vec3(0.0f);
  Vec3 pc = lens + to_camera_.vector(ray.d) * ((aperture_radius > 0 ? focus_distance : 1.0f) / cos_theta);
  if (pc.z >= 0) return 0;
  float px = pc.x / -pc.z, py = pc.y / -pc.z;
  Vec2 r{(px - left) / (right - left) * width_, (top - py) / (top - bottom) * height_};
  if (r.x < 0 || r.x >= width_ || r.y < 0 || r.y >= height_) return 0;
  if (raster) *raster = r;
  float area = (right - left) * (top - bottom);
  float c2 = cos_theta * cos_theta;
  return 1.0f / (area * lens_area() * c2 * c2);
}

bool Camera::raster_of_direction(Vec3 d, Vec2 &raster, float &cos_theta) const {
  cos_theta = dot(d, forward_);
  if (type != Type::Perspective || cos_theta <= 0) return false;
  Vec3 pc = to_camera_.vector(d) * (1.0f / cos_theta);
  if (pc.z >= 0) return false;
  float px = pc.x / -pc.z, py = pc.y / -pc.z;
  raster = {(px - left) / (right - left) * width_, (top - py) / (top - bottom) * height_};
  return true;
}

bool Camera::raster_through_lens(Vec3 lens_point, Vec3 d, Vec2 &raster, float &cos_theta) const {
  if (!(aperture_radius > 0)) return raster_of_direction(d, raster, cos_theta);
  cos_theta = dot(d, forward_);
  if (cos_theta <= 0) return false;
  if (type == Type::Orthographic) {
    const Vec3 lens = to_camera_.point(lens_point);
    const Vec3 pc = lens + to_camera_.vector(d) * (focus_distance / cos_theta);
    raster = {(pc.x - left) / (right - left) * width_, (top - pc.y) / (top - bottom) * height_};
    return aperture_covers(Vec2(lens.x - pc.x, lens.y - pc.y));
  }
  // As importance(): in camera space, through the ray's point on the focal plane.
  Vec3 pc = to_camera_.vector(lens_point - position()) + to_camera_.vector(d) * (focus_distance / cos_theta);
  if (pc.z >= 0) return false;
  float px = pc.x / -pc.z, py = pc.y / -pc.z;
  raster = {(px - left) / (right - left) * width_, (top - py) / (top - bottom) * height_};
  return true;
}

bool Camera::raster_of_point(Vec3 p, Vec2 &raster, Vec3 &plane_point) const {
  Vec3 pc = to_camera_.point(p);
  if (type != Type::Orthographic || pc.z >= 0) return false;
  raster = {(pc.x - left) / (right - left) * width_, (top - pc.y) / (top - bottom) * height_};
  plane_point = to_world.point(Vec3(pc.x, pc.y, 0));
  return true;
}

float Camera::image_plane_area() const {
  return viewplane_area() * length(cross(to_world.column(0), to_world.column(1)));
}

Vec2 Camera::lens_of_point(Vec3 p) const {
  Vec3 pc = to_camera_.point(p);
  return {pc.x, pc.y};
}

bool Camera::aperture_covers(Vec2 offset) const {
  // A hair of slack: an offset lens_sample made, carried through a world point and back.
  const float r = aperture_radius * (1 + 1e-4f);
  if (blades < 3) return offset.x * offset.x + offset.y * offset.y <= r * r;
  // Inside every edge: the polygon's corners are at rotation + k corner, its edges at
  // r cos(corner / 2) from the centre, their normals half a corner further round.
  const float corner = 2.0f * kPi / float(blades), inner = r * std::cos(0.5f * corner);
  for (int k = 0; k < blades; ++k) {
    const float a = blade_rotation + corner * (float(k) + 0.5f);
    if (offset.x * std::cos(a) + offset.y * std::sin(a) > inner) return false;
  }
  return true;
}

float Camera::aperture_area() const {
  if (!(aperture_radius > 0)) return 1.0f;
  const float r2 = aperture_radius * aperture_radius;
  if (blades >= 3) return 0.5f * float(blades) * std::sin(2.0f * kPi / float(blades)) * r2;
  return kPi * r2;
}

void Camera::importance_pdf(const Ray &ray, float &pdf_pos, float &pdf_dir) const {
  pdf_pos = pdf_dir = 0;
  if (type != Type::Perspective) return;
  float cos_theta = dot(ray.d, forward_);
  if (cos_theta <= 0 || importance(ray, nullptr) == 0) return;
  float area = (right - left) * (top - bottom);
  pdf_pos = 1.0f / lens_area();
  pdf_dir = 1.0f / (area * cos_theta * cos_theta * cos_theta);
}

bool Camera::sample_importance(Vec3 ref, Vec2 u_lens, ImportanceSample &out) const {
  if (type != Type::Perspective) return false;
  Vec2 lens = aperture_radius > 0 ? lens_sample(u_lens) : Vec2(0, 0);
  out.lens_point = to_world.point(Vec3(lens.x, lens.y, 0));
  Vec3 to_lens = out.lens_point - ref;
  float d2 = length_squared(to_lens);
  if (!(d2 > 0)) return false;
  out.dist = std::sqrt(d2);
  out.wi = to_lens / out.dist;
  // The camera sees nothing nearer than clip_start or beyond clip_end.
  float depth = dot(ref - position(), forward_);
  if (depth < clip_start || depth > clip_end) return false;
  float cos_lens = absdot(forward_, out.wi);
  if (cos_lens <= 0) return false;
  out.pdf = d2 / (cos_lens * lens_area());
  out.We = importance(Ray{out.lens_point, -out.wi, kInf}, &out.raster);
  out.pdf_dir = 1.0f / ((right - left) * (top - bottom) * cos_lens * cos_lens * cos_lens);  // as importance_pdf
  return out.We > 0;
}
}  // namespace rdv
