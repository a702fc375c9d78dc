// Where light subpaths start: a point on the light and a direction it emits in, with
// the densities BDPT's MIS needs. Point and spot lights with a radius emit from their
// sphere (sphere_lamp.h): a point on it, then a direction leaving it, as next-event
// estimation and the rays that hit it see the same sphere.
#include "core/sampling.h"
#include "lights/light.h"
#include "lights/environment.h"
#include "lights/sphere_lamp.h"
#include "lights/volume_light.h"

namespace rdv {

bool light_is_delta_position(const Light &l) {
  return (l.type == LightType::Point || l.type == LightType::Spot) && l.radius == 0;
}
bool light_is_delta_direction(const Light &l) { return l.type == LightType::Sun && l.radius == 0; }

namespace {
// The sine of the widest angle off the axis a spread area lamp emits at: half its spread.
float spread_sin_max(const Light &l) { return 1.0f / std::sqrt(1.0f + sqr(l.tan_spread)); }
}  // namespace

bool sample_emission(const Light &l, Vec2 u_pos, Vec2 u_dir, Vec3 u_volume, Vec3 center, float radius,
                     EmissionSample &out) {
  switch (l.type) {
    case LightType::Point:
    case LightType::Spot: {
      if (l.radius > 0) {
        Vec3 n, d;
        out.pdf_pos = sample_sphere_lamp_point(l, u_pos, out.ray.o, n);
        if (!sample_sphere_lamp_direction(l, n, u_dir, d)) return false;
        out.pdf_dir = sphere_lamp_direction_pdf(l, n, d);
        out.ray = {out.ray.o, d, kInf};
        out.n = n;
        out.Le = sphere_lamp_radiance(l, n, d, 1.0f);  // by_distance: at 1 (EmissionSample)
        return out.pdf_dir > 0 && !is_black(out.Le);
      }
      Vec3 d;
      if (l.type == LightType::Spot) {
        d = uniform_cone(l.axis, l.cos_half_spot, u_dir);
        out.pdf_dir = 1.0f / (2.0f * kPi * (1.0f - l.cos_half_spot));
      } else {
        d = uniform_sphere(u_dir);
        out.pdf_dir = uniform_sphere_pdf();
      }
      out.pdf_pos = 1;  // a delta position
      out.ray = {l.position, d, kInf};
      out.n = Vec3(0.0f);
      out.Le = lamp_radiance(l, l.position, d, 1.0f);  // intensity
      return !is_black(out.Le);
    }
    case LightType::Area:
    case LightType::Triangle: {
      Vec3 p;
      if (l.type == LightType::Area) {
        if (l.ellipse) {
          Vec2 q = concentric_disk(u_pos);
          p = l.position + l.edge_u * (0.5f * q.x) + l.edge_v * (0.5f * q.y);
        } else {
          p = l.position + l.edge_u * (u_pos.x - 0.5f) + l.edge_v * (u_pos.y - 0.5f);
        }
      } else {
        Vec2 b = uniform_triangle(u_pos);
        p = l.p0 + l.edge_u * b.x + l.edge_v * b.y;
      }
      Vec3 n = l.axis;
      Vec2 ud = u_dir;
      float side_pdf = 1.0f;
      if (l.type == LightType::Triangle) {  // two-sided: pick a side
        side_pdf = 0.5f;
        if (ud.x < 0.5f) { n = -n; ud.x *= 2.0f; }
        else ud.x = (ud.x - 0.5f) * 2.0f;
        ud.x = std::min(ud.x, 0.99999994f);
      }
      Vec3 local = cosine_hemisphere(ud);
      float pdf_dir = cosine_hemisphere_pdf(local.z);
      if (l.type == LightType::Area && l.tan_spread > 0) {
        // A spread lamp emits only within the slats' cone: cosine-distributed within it (the
        // disk cosine_hemisphere projects, shrunk to the cone's sine).
        const float sin_max = spread_sin_max(l);
        local = Vec3(local.x * sin_max, local.y * sin_max, safe_sqrt(1.0f - (sqr(local.x) + sqr(local.y)) * sqr(sin_max)));
        pdf_dir = local.z * kInvPi / sqr(sin_max);
      }
      Vec3 d = Frame(n).to_world(local);
      out.pdf_pos = l.inv_area;
      out.pdf_dir = side_pdf * pdf_dir;
      out.ray = {p, d, kInf};
      out.n = n;
      out.Le = l.type == LightType::Area ? lamp_radiance(l, p, d, 1.0f) : l.radiance;  // an area lamp's spread
      return out.pdf_dir > 0 && !is_black(out.Le);
    }
    case LightType::Sun:
    case LightType::Background: {
      // Direction toward the light, then an origin on a disk covering the scene.
      Vec3 to_light;
      Color L;
      if (l.type == LightType::Background && l.env) {  // importance-sampled HDRI
        if (!l.env->sample(u_dir, to_light, L, out.pdf_dir)) return false;
      } else if (l.type == LightType::Background) {
        to_light = uniform_sphere(u_dir);
        out.pdf_dir = uniform_sphere_pdf();
        L = l.radiance;
      } else if (l.radius > 0) {
        Frame f(-l.axis);
        Vec2 q = concentric_disk(u_dir) * l.radius;
        to_light = normalize(-l.axis + f.s * q.x + f.t * q.y);
        float c = dot(-l.axis, to_light);
        out.pdf_dir = l.inv_area / (c * c * c);
        L = l.radiance * out.pdf_dir;
      } else {
        to_light = -l.axis;
        out.pdf_dir = 1.0f;
        L = l.radiance;
      }
      Frame f(to_light);
      Vec2 q = concentric_disk(u_pos) * radius;
      Vec3 o = center + to_light * radius + f.s * q.x + f.t * q.y;
      out.ray = {o, -to_light, kInf};
      out.pdf_pos = 1.0f / (kPi * radius * radius);
      out.n = -to_light;
      out.Le = L;
      return true;
    }
    case LightType::Volume: {
      // A point by emitted power, a direction uniform over the sphere (isotropic).
      Vec3 p = l.volume->sample(u_pos, u_volume, &out.pdf_pos);
      out.ray = {p, uniform_sphere(u_dir), kInf};
      out.pdf_dir = uniform_sphere_pdf();
      out.n = Vec3(0.0f);
      out.Le = l.volume->medium().emission_at(p);
      return out.pdf_pos > 0 && !is_black(out.Le);
    }
  }
  return false;
}

void emission_pdf(const Light &l, Vec3 p, Vec3 n, Vec3 dir, float radius, float &pdf_pos, float &pdf_dir) {
  pdf_pos = pdf_dir = 0;
  switch (l.type) {
    case LightType::Point:
    case LightType::Spot:
      if (l.radius > 0) {  // n: the sphere's normal at p
        pdf_pos = sphere_lamp_point_pdf(l, n);
        pdf_dir = sphere_lamp_direction_pdf(l, n, dir);
      } else if (l.type == LightType::Point) {
        pdf_pos = 1;
        pdf_dir = uniform_sphere_pdf();
      } else {
        pdf_pos = 1;
        pdf_dir = dot(l.axis, dir) > l.cos_half_spot ? 1.0f / (2.0f * kPi * (1.0f - l.cos_half_spot)) : 0.0f;
      }
      break;
    case LightType::Area:
      pdf_pos = l.inv_area;
      pdf_dir = cosine_hemisphere_pdf(dot(l.axis, dir));
      if (l.tan_spread > 0 && pdf_dir > 0) {  // within the spread's cone only (sample_emission)
        const float c = dot(l.axis, dir), sin_max = spread_sin_max(l);
        pdf_dir = 1.0f - c * c <= sqr(sin_max) ? c * kInvPi / sqr(sin_max) : 0.0f;
      }
      break;
    case LightType::Triangle:
      pdf_pos = l.inv_area;
      pdf_dir = 0.5f * absdot(l.axis, dir) * kInvPi;
      break;
    case LightType::Sun:
    case LightType::Background:
      pdf_pos = 1.0f / (kPi * radius * radius);
      pdf_dir = light_pdf(l, Vec3(0.0f), -dir, kInf);
      if (light_is_delta_direction(l)) pdf_dir = 0;  // cannot be chosen by chance
      break;
    case LightType::Volume:
      pdf_pos = l.volume->pdf(p);
      pdf_dir = uniform_sphere_pdf();
      break;
  }
  (void)p;
  (void)n;
}

}  // namespace rdv
