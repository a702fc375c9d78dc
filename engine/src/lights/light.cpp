#include "lights/light.h"
#include <algorithm>
#include "core/sampling.h"
#include "lights/environment.h"
#include "lights/lamp_emission.h"
#include "lights/rectangle_lamp.h"
#include "lights/sphere_lamp.h"
#include "lights/volume_light.h"

namespace rdv {

// Cycles 3.4's spot_attenuation: cos(theta) x smoothstep over the blend region.
float spot_attenuation(const Light &l, Vec3 dir_from_light) {
  float c = dot(l.axis, dir_from_light);
  if (c <= l.cos_half_spot) return 0.0f;
  float t = c - l.cos_half_spot;
  if (l.spot_smooth > 0 && t < l.spot_smooth) c *= smoothstep(0.0f, l.spot_smooth, t);
  return c;
}

Color lamp_radiance(const Light &l, Vec3 p, Vec3 dir, float distance) {
  Color L = l.radiance;
  if (l.type == LightType::Spot) L *= spot_attenuation(l, dir);
  if (l.type == LightType::Area) {
    const float c = dot(l.axis, dir);
    if (!(c > 0)) return Color(0.0f);  // one-sided
    if (l.tan_spread > 0) {            // Cycles' light_spread_attenuation
      const float tan_off_axis = safe_sqrt(1.0f - c * c) / c;
      L *= std::max((1.0f - l.tan_spread * tan_off_axis) * l.normalize_spread, 0.0f);
    }
  }
  if (l.emission && !is_black(L)) L = L * l.emission->eval(p, dir, distance);
  return L;
}

UserLight::UserLight() = default;
UserLight::UserLight(UserLight &&) noexcept = default;
UserLight &UserLight::operator=(UserLight &&) noexcept = default;
UserLight::~UserLight() = default;

UserLight make_light(Params &p, const ImageBuffers *images) {
  UserLight user;
  Light &l = user.light;
  std::string type = p.get_string("type", "point");
  Color color = p.get_vec3("color", Color(1.0f));
  if (color.x < 0 || color.y < 0 || color.z < 0) fail(p.what() + ": 'color' must not be negative");
  Transform t;
  if (p.has("transform")) {
    t = p.get_transform("transform", Transform());
  } else {
    Vec3 pos = p.get_vec3("position", Vec3(0.0f));
    Vec3 dir = p.get_vec3("direction", Vec3(0, 0, -1));
    if (length(dir) == 0) fail(p.what() + ": 'direction' must not be zero");
    nlohmann::json la = {{"look_at", {{"from", {pos.x, pos.y, pos.z}}, {"to", {pos.x + dir.x, pos.y + dir.y, pos.z + dir.z}}}}};
    t = parse_transform(la, p.what());
  }
  l.position = t.column(3);
  Vec3 z = t.column(2);
  if (length(z) == 0) fail(p.what() + ": 'transform' has a zero Z axis");
  l.axis = -normalize(z);
  auto non_negative = [&](const char *key, float fallback) {
    float v = p.get_float(key, fallback);
    if (v < 0) fail(p.what() + ": '" + key + "' must not be negative");
    return v;
  };
  if (type == "point" || type == "spot") {
    l.type = type == "point" ? LightType::Point : LightType::Spot;
    float power = non_negative("power", 1000.0f);
    l.radius = non_negative("radius", 0.1f);
    l.inv_area = l.radius > 0 ? 1.0f / (kPi * l.radius * l.radius) : 1.0f;
    l.radiance = color * (power * kInv4Pi * l.inv_area);
    if (l.type == LightType::Spot) {
      float size = clampf(p.get_float("spot_size", 0.785398f), 1e-4f, kPi);
      float blend = clampf(p.get_float("spot_blend", 0.15f), 0.0f, 1.0f);
      l.cos_half_spot = std::cos(size * 0.5f);
      l.spot_smooth = (1.0f - l.cos_half_spot) * blend;
    }
  } else if (type == "sun") {
    l.type = LightType::Sun;
    float strength = non_negative("strength", 1.0f);
    float angle = clampf(p.get_float("angle", 0.00918043f), 0.0f, kPi * 0.999f);
    l.radius = std::tan(angle * 0.5f);
    l.inv_area = l.radius > 0 ? 1.0f / (kPi * l.radius * l.radius) : 1.0f;
    l.radiance = color * strength;
  } else if (type == "area") {
    l.type = LightType::Area;
    float power = non_negative("power", 10.0f);
    std::string shape = p.get_string("shape", "square");
    float size = p.get_float("size", 1.0f);
    float size_y = p.get_float("size_y", 1.0f);
    if (shape == "square" || shape == "disk") size_y = size;
    else if (shape != "rectangle" && shape != "ellipse")
      fail(p.what() + ": 'shape' must be square, rectangle, disk or ellipse, got '" + shape + "'");
    l.ellipse = shape == "disk" || shape == "ellipse";
    l.edge_u = t.column(0) * size;  // Cycles scales the light's axes by the object's scale
    l.edge_v = t.column(1) * size_y;
    float area = length(cross(l.edge_u, l.edge_v)) * (l.ellipse ? kPi * 0.25f : 1.0f);
    if (!(area > 0)) fail(p.what() + ": the area light has zero area (size or scale is 0)");
    l.inv_area = 1.0f / area;
    l.radiance = color * (0.25f * power * l.inv_area);
    // Spread s (radians, 180 degrees: none, its smallest 1 degree), as Cycles 3.4 turns it into
    // the slats' tangent, tan((pi - s) / 2), and the normalisation that keeps the lamp's power,
    // 2 / (2 - s cot(s / 2)) (the integral of cos x (1 - tan x tan a) sin x over 0..pi/2 - a).
    // In double: the denominator is about s^2 / 6, a cancellation that Cycles' float leaves
    // several percent off below a few degrees.
    const double spread = std::clamp(double(p.get_float("spread", kPi)), kPi / 180.0, double(kPi));
    if (spread < kPi) {
      const double cot_half = 1.0 / std::tan(0.5 * spread);
      l.tan_spread = float(cot_half);
      l.normalize_spread = float(2.0 / (2.0 - spread * cot_half));
    }
  } else {
    fail(p.what() + ": unknown light type '" + type + "' (point, spot, sun, area)");
  }
  if (const nlohmann::json *e = p.get_json("emission")) {
    // The lamp's node tree, once its shape is known: what varies (by direction, over the
    // lamp, with the distance) stays a graph; what does not is folded into the radiance.
    Color constant;
    user.emission = LampEmission::parse(*e, t, l, images, p.what(), user.warnings, constant);
    l.emission = user.emission.get();
    l.by_distance = l.emission && l.emission->depends_on_distance();
    if (!l.emission) l.radiance = l.radiance * constant;
  }
  // "visible_camera" (older files) is the default of "visibility": {"camera": ...}.
  const bool camera = p.get_bool("visible_camera", false);
  l.visibility = visibility::from_params(p, visibility::kNonCamera | (camera ? visibility::kCamera : 0));
  l.shadow_catcher = p.get_bool("shadow_catcher", true);
  // Blender's default, 1024, is no limit in practice.
  l.max_bounces = std::max(-1, p.get_int("max_bounces", -1));
  p.check_all_used();
  return user;
}

Light make_triangle_light(Vec3 a, Vec3 b, Vec3 c, Color radiance) {
  Light l;
  l.type = LightType::Triangle;
  l.p0 = a;
  l.edge_u = b - a;
  l.edge_v = c - a;
  Vec3 n = cross(l.edge_u, l.edge_v);
  l.axis = normalize(n);
  l.inv_area = 2.0f / length(n);
  l.radiance = radiance;
  return l;
}

Light make_background_light(Color radiance) {
  Light l;
  l.type = LightType::Background;
  l.radiance = radiance;
  l.visibility = visibility::kAll;  // the world is the background
  return l;
}

Light make_environment_light(const EnvironmentMap *env) {
  Light l;
  l.type = LightType::Background;
  l.env = env;
  l.radiance = env->mean();
  l.visibility = visibility::kAll;  // the world is the background
  return l;
}

Light make_volume_light(const VolumeEmitter *emitter) {
  Light l;
  l.type = LightType::Volume;
  l.volume = emitter;
  return l;
}

void compute_light_power(Light &l, float scene_radius) {
  float a = average(l.radiance);  // environment: its mean radiance
  float disk = kPi * scene_radius * scene_radius;
  switch (l.type) {
    case LightType::Point:
    case LightType::Spot: l.power = 4 * kPi * a / l.inv_area * (l.emission ? l.emission->mean_luminance() : 1.0f); break;
    case LightType::Area: l.power = kPi * a / l.inv_area * (l.emission ? l.emission->mean_luminance() : 1.0f); break;
    case LightType::Triangle: l.power = 2 * kPi * a / l.inv_area; break;
    case LightType::Sun: l.power = a * disk; break;
    case LightType::Background: l.power = kPi * a * disk; break;
    case LightType::Volume: l.power = l.volume->power(); break;
  }
  if (!std::isfinite(l.power)) l.power = 0;
}

// Point on an elliptic area light from u, relative to its centre.
static Vec3 ellipse_offset(const Light &l, Vec2 u) {
  const Vec2 d = concentric_disk(u);
  return l.edge_u * (0.5f * d.x) + l.edge_v * (0.5f * d.y);
}

// Converts an area density on a surface with normal n at point p into solid angle at ref.
static bool to_solid_angle(Vec3 ref, Vec3 p, Vec3 n, float inv_area, bool two_sided, LightSample &s) {
  Vec3 d = p - ref;
  float dist2 = length_squared(d);
  if (!(dist2 > 0)) return false;
  s.dist = std::sqrt(dist2);
  s.wi = d / s.dist;
  float cos_l = -dot(n, s.wi);
  if (two_sided) cos_l = std::fabs(cos_l);
  if (cos_l <= 1e-7f) return false;
  s.pdf = dist2 * inv_area / cos_l;
  s.p = p;
  return std::isfinite(s.pdf);
}

bool sample_light(const Light &l, Vec3 ref, Vec2 u, Vec3 u_volume, LightSample &s) {
  switch (l.type) {
    case LightType::Point:
    case LightType::Spot: {
      if (l.radius > 0) {  // the lamp's sphere (sphere_lamp.h)
        if (!sample_sphere_lamp_from(l, ref, u, s.wi, s.dist, s.pdf)) return false;
        s.p = ref + s.wi * s.dist;
        s.L = sphere_lamp_radiance(l, normalize(s.p - l.position), -s.wi, sphere_lamp_distance(l, ref));
        return !is_black(s.L);
      }
      Vec3 to_ref = ref - l.position;
      float d2 = length_squared(to_ref);
      if (!(d2 > 0)) return false;
      s.dist = std::sqrt(d2);
      s.wi = -to_ref / s.dist;
      s.p = l.position;
      s.pdf = 1;
      s.L = lamp_radiance(l, l.position, -s.wi, s.dist) / d2;  // intensity / r^2
      return !is_black(s.L);
    }
    case LightType::Sun: {
      Vec3 to_light = -l.axis;
      if (l.radius > 0) {
        Frame f(to_light);
        Vec2 d = concentric_disk(u) * l.radius;
        s.wi = normalize(to_light + f.s * d.x + f.t * d.y);
        float c = dot(to_light, s.wi);
        s.pdf = l.inv_area / (c * c * c);
        s.L = l.radiance * s.pdf;  // radiance E / (pi r^2 cos^3): contribution E cos
      } else {
        s.wi = to_light;
        s.pdf = 1;
        s.L = l.radiance;
      }
      s.dist = kInf;
      return true;
    }
    case LightType::Area: {
      if (l.ellipse) {
        const Vec3 p = l.position + ellipse_offset(l, u);
        if (!to_solid_angle(ref, p, l.axis, l.inv_area, false, s)) return false;
      } else {  // by solid angle, only the part whose light can reach ref (rectangle_lamp.h)
        if (!sample_rectangle_lamp_from(l, ref, u, s.p, s.pdf)) return false;
        const Vec3 d = s.p - ref;
        const float dist2 = length_squared(d);
        if (!(dist2 > 0)) return false;
        s.dist = std::sqrt(dist2);
        s.wi = d / s.dist;
      }
      s.L = lamp_radiance(l, s.p, -s.wi, s.dist);
      return !is_black(s.L);
    }
    case LightType::Triangle: {
      Vec2 b = uniform_triangle(u);
      Vec3 p = l.p0 + l.edge_u * b.x + l.edge_v * b.y;
      if (!to_solid_angle(ref, p, l.axis, l.inv_area, true, s)) return false;
      s.L = l.radiance;
      s.n = l.axis;
      s.error = l.error;
      return true;
    }
    case LightType::Background: {
      if (l.env) {
        s.dist = kInf;
        return l.env->sample(u, s.wi, s.L, s.pdf) && !is_black(s.L);
      }
      s.wi = uniform_sphere(u);
      s.pdf = uniform_sphere_pdf();
      s.dist = kInf;
      s.L = l.radiance;
      return true;
    }
    case LightType::Volume: {
      float pdf_volume;
      Vec3 p = l.volume->sample(u, u_volume, &pdf_volume);
      Vec3 d = p - ref;
      float dist2 = length_squared(d);
      if (!(pdf_volume > 0) || !(dist2 > 0)) return false;
      s.dist = std::sqrt(dist2);
      s.wi = d / s.dist;
      s.p = p;
      s.pdf = pdf_volume * dist2;  // no cosine: a point in a volume
      s.L = l.volume->medium().emission_at(p);
      s.medium = l.volume->medium_index();
      return !is_black(s.L) && std::isfinite(s.pdf);
    }
  }
  return false;
}

float light_pdf(const Light &l, Vec3 ref, Vec3 wi, float dist) {
  switch (l.type) {
    case LightType::Point:
    case LightType::Spot: {
      (void)wi;
      (void)dist;  // a direction toward the sphere: the cone's density (sphere_lamp.h)
      return l.radius > 0 ? sphere_lamp_cone_pdf(l, ref) : 0.0f;
    }
    case LightType::Sun: {
      if (l.radius == 0) return 0;
      float c = dot(-l.axis, wi);
      if (c <= 0 || (1.0f - c * c) > sqr(l.radius * c)) return 0;  // tan(theta) > radius
      return l.inv_area / (c * c * c);
    }
    case LightType::Area: {
      if (!l.ellipse) return rectangle_lamp_pdf(l, ref, ref + wi * dist);
      float cos_l = -dot(l.axis, wi);
      return cos_l > 0 ? dist * dist * l.inv_area / cos_l : 0.0f;
    }
    case LightType::Triangle: {
      float cos_l = std::fabs(dot(l.axis, wi));
      return cos_l > 0 ? dist * dist * l.inv_area / cos_l : 0.0f;
    }
    case LightType::Background: return l.env ? l.env->pdf(wi) : uniform_sphere_pdf();
    case LightType::Volume: return l.volume->pdf(ref + wi * dist) * dist * dist;
  }
  return 0;
}

bool intersect_light(const Light &l, const Ray &ray, float tmax, float &t, Color &L) {
  switch (l.type) {
    case LightType::Point:
    case LightType::Spot: {
      if (l.radius == 0 || !intersect_sphere_lamp(l, ray.o, ray.d, tmax, t)) return false;
      L = sphere_lamp_radiance(l, normalize(ray.o + ray.d * t - l.position), -ray.d, sphere_lamp_distance(l, ray.o));
      return !is_black(L);
    }
    case LightType::Area: {
      float denom = dot(ray.d, l.axis);
      if (denom >= 0) return false;  // one-sided: only its emitting face is visible
      t = dot(l.position - ray.o, l.axis) / denom;
      if (!(t > 0 && t < tmax)) return false;
      Vec3 q = ray.o + ray.d * t - l.position;
      float uu = dot(q, l.edge_u) / length_squared(l.edge_u);
      float vv = dot(q, l.edge_v) / length_squared(l.edge_v);
      bool inside = l.ellipse ? sqr(2 * uu) + sqr(2 * vv) <= 1.0f : std::fabs(uu) <= 0.5f && std::fabs(vv) <= 0.5f;
      if (!inside) return false;
      L = lamp_radiance(l, ray.o + ray.d * t, -ray.d, t);
      return !is_black(L);
    }
    default: return false;
  }
}

Color infinite_light_radiance(const Light &l, Vec3 d) {
  if (l.type == LightType::Background) return l.env ? l.env->eval(d) : l.radiance;
  if (l.type == LightType::Sun && l.radius > 0) {
    float pdf = light_pdf(l, Vec3(0.0f), d, kInf);
    return pdf > 0 ? l.radiance * pdf : Color(0.0f);
  }
  return Color(0.0f);
}

}  // namespace rdv
