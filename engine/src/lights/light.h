// Light sources, in Blender 3.4 / Cycles units (intern/cycles/blender/light.cpp):
//  point/spot: power P in Watts, radiant intensity P / (4 pi); with a radius, a sphere
//              of that radius emitting radiance P / (4 pi * pi r^2) (sphere_lamp.h);
//  spot:       times cos(theta) * smoothstep of the cone blend;
//  sun:        irradiance E; with an angle, directions over a disk of radius
//              tan(angle / 2) at unit distance, radiance E / (pi r^2 cos^3);
//  area:       one-sided (local -Z), radiance P / (4 A);
//  triangle:   an emissive mesh triangle, radiance from its material, two-sided;
//  background: constant world radiance;
//  volume:     a bounded emissive medium (lights/volume_light.h), radiance per unit
//              length from the medium, isotropic.
// One plain struct, dispatched by a switch on the type.
#pragma once
#include <memory>
#include <string>
#include <vector>
#include "core/math.h"
#include "core/params.h"
#include "scene/ray_visibility.h"
#include "textures/image_buffers.h"

namespace rdv {

class EnvironmentMap;  // lights/environment.h
class LampEmission;    // lights/lamp_emission.h
class VolumeEmitter;   // lights/volume_light.h

enum class LightType : uint8_t { Point, Spot, Sun, Area, Triangle, Background, Volume };

struct Light {
  LightType type = LightType::Point;
  Color radiance{0.0f};  // see the table above; sun: irradiance E
  Vec3 position{0.0f};
  Vec3 axis{0, 0, -1};   // the direction the light shines (spot, sun, area)
  float radius = 0;      // point/spot disk radius; sun: tan(angle / 2)
  float inv_area = 1;    // of the emitting disk / rectangle / triangle
  // spot
  float cos_half_spot = -1, spot_smooth = 0;
  // area: Cycles' Spread, a soft box's slats: emission falls as 1 - tan_spread tan(angle off the
  // axis), scaled by normalize_spread to keep the lamp's power; tan_spread 0: 180 degrees, none.
  float tan_spread = 0, normalize_spread = 1;
  // area: centre = position, half axes; triangle: p0 + edges
  Vec3 edge_u{0.0f}, edge_v{0.0f};
  bool ellipse = false;
  Vec3 p0{0.0f};
  // triangle: the mesh triangle it is; textured: its material's emission varies over
  // it (radiance holds the mean, and Scene::sample_light evaluates the texture).
  uint32_t instance = 0, prim = 0;
  bool textured = false;
  // Triangle of a moving instance or deforming mesh (motion blur): the fields above are
  // where it is at its frame; Scene::light_now places it at a sample's shutter time.
  bool moves = false;
  // Whether it lights the catcher pass of a shadow catcher (integrators/path/
  // shadow_catcher.h), as Cycles 3.4: a lamp unless its object's Object > Visibility >
  // Shadow Catcher is off (on by default for Blender's lights: a light of the footage; one
  // turned off is the synthetic objects' own and brightens the pass: parameter
  // "shadow_catcher", default true), an emissive triangle whose instance is a catcher, the
  // world always.
  bool shadow_catcher = false;  // (in the bools' padding)
  // Its radiance depends on how far the light travels to the point it lights (a Light
  // Falloff in its node tree or its material: Cycles' ray length; a sphere lamp's from its
  // centre, sphere_lamp.h). Everything that evaluates emission passes that distance; a light
  // subpath weighs its first segment by it once the segment is traced (bdpt/subpaths.cpp).
  bool by_distance = false;
  Vec3 error{0.0f};      // triangle: rounding error bound of its points (core/ray_offset.h); Embree can hit it
  float power = 0;       // for light selection (scalar)
  // The kinds of ray that see it (scene/ray_visibility.h). Lamps: camera rays only when
  // asked (Cycles 3.4 never shows lamps to the camera, it does show them in reflections);
  // without the shadow bit a lamp casts no shadows (Cycles' Cast Shadow). Emissive
  // triangles: their instance's; the world: its own.
  uint32_t visibility = visibility::kNonCamera;
  bool visible_camera() const { return visibility & visibility::kCamera; }
  // Cycles' Light > Max Bounces (lamps: light.cycles.max_bounces): the light lights only
  // the paths of at most this many bounces, as the scene's Max Bounces would for it alone
  // (0: direct light only); -1: no limit. A function of the path, so every strategy of
  // every integrator keeps the same paths.
  int max_bounces = -1;
  // Whether it lights a path with `scatterings` scattering vertices (passes through
  // transparent layers not counted): scatterings - 1 bounces.
  bool lights_path(int scatterings) const { return max_bounces < 0 || scatterings - 1 <= max_bounces; }
  // What blocks the last segment of a path from a scattering vertex to this light: the
  // instances visible to shadow rays, or nothing for a lamp that casts no shadows (an
  // emissive object hidden from shadow rays only casts no shadow itself).
  uint32_t occluders() const {
    return type == LightType::Triangle ? visibility::kShadow : visibility & visibility::kShadow;
  }
  // Background: an importance-sampled equirectangular HDRI (owned by the Scene), or
  // null for the constant `radiance`.
  const EnvironmentMap *env = nullptr;
  // Volume: the emitter (owned by the Scene); its medium is where the light emits.
  const VolumeEmitter *volume = nullptr;
  // Point / spot: a node tree that shapes the emission by direction (an IES profile), owned
  // with the light (UserLight); null: the same in every direction (folded into radiance).
  const LampEmission *emission = nullptr;

  bool is_delta() const {
    return ((type == LightType::Point || type == LightType::Spot) && radius == 0) ||
           (type == LightType::Sun && radius == 0);
  }
  bool is_infinite() const { return type == LightType::Sun || type == LightType::Background; }
};

struct LightSample {
  Vec3 wi;        // from the shaded point toward the light
  float dist = kInf;
  Vec3 p;         // point on the light (finite lights)
  Vec3 n{0.0f};   // emissive triangles: their normal and the rounding error of p, so a
  Vec3 error{0.0f};  // shadow ray stops short of the triangle itself (shadow_ray)
  Color L{0.0f};  // radiance (or intensity-derived value for delta lights) arriving
  float pdf = 0;  // solid angle; 1 for delta lights
  // Volume lights: the point emits only if it is inside the light's medium, which the
  // caller learns from the media its shadow ray passes (MediumStack).
  int medium = -1;
};

// Cycles 3.4's spot falloff along a direction leaving the light.
float spot_attenuation(const Light &light, Vec3 dir_from_light);
// What a point, spot or area lamp emits from its point p along a unit direction leaving it
// toward a point `distance` away: its radiance (a delta lamp: intensity), the spot's falloff,
// an area lamp's one side and spread, and its node tree's share there, in that direction at
// that distance.
Color lamp_radiance(const Light &light, Vec3 p, Vec3 dir_from_light, float distance);

// A user light as make_light builds it: the Light, the node tree it points to (keep them
// together) and what the parameters made it warn of.
struct UserLight {
  UserLight();
  UserLight(UserLight &&) noexcept;
  UserLight &operator=(UserLight &&) noexcept;
  ~UserLight();  // these four in light.cpp, where LampEmission is complete
  Light light;
  std::unique_ptr<LampEmission> emission;
  std::vector<std::string> warnings;
};
// Builds a user light from its parameters (rdv_scene_add_light).
// Image nodes in its tree naming a "buffer" find it in `images` (null: none).
UserLight make_light(Params &p, const ImageBuffers *images = nullptr);
Light make_triangle_light(Vec3 a, Vec3 b, Vec3 c, Color radiance);
Light make_background_light(Color radiance);
Light make_environment_light(const EnvironmentMap *env);
Light make_volume_light(const VolumeEmitter *emitter);
// scene_radius: radius of the scene's bounding sphere, for the power of infinite lights.
void compute_light_power(Light &light, float scene_radius);

// u: the point on the light (a volume light: the choice of region or voxel), u_volume:
// volume lights only, the point in that region or voxel.
bool sample_light(const Light &light, Vec3 ref, Vec2 u, Vec3 u_volume, LightSample &out);
// Solid-angle density of sample_light choosing direction wi from ref, given the ray
// reached the light at distance dist (triangles: also needs light normal via geometry).
float light_pdf(const Light &light, Vec3 ref, Vec3 wi, float dist);
// Analytic lights a ray can hit (point and spot spheres, rectangles, ellipses). Returns radiance.
bool intersect_light(const Light &light, const Ray &ray, float tmax, float &t, Color &L);
// Radiance of an infinite light seen along an escaping direction.
Color infinite_light_radiance(const Light &light, Vec3 d);

// ---- Emission sampling, for light subpaths (BDPT) -- lights/light_emission.cpp ----
struct EmissionSample {
  Ray ray;          // leaves the light
  Vec3 n{0.0f};     // emitting surface normal; zero for point-like lights (no cosine)
  Color Le{0.0f};   // radiance (or intensity for delta-position lights) along ray; a light
                    // whose emission depends on the distance (by_distance): toward a point 1 away
  float pdf_pos = 0;  // area density of the origin (1 for delta positions; 1/(pi R^2) for infinite lights)
  float pdf_dir = 0;  // solid-angle density of the direction (1 for delta directions)
};
// scene_center / scene_radius: the disk infinite lights emit through. u_volume: as for
// sample_light (volume lights: u_pos chooses the region or voxel, u_volume the point).
bool sample_emission(const Light &light, Vec2 u_pos, Vec2 u_dir, Vec3 u_volume, Vec3 scene_center,
                     float scene_radius, EmissionSample &out);
// Densities with which sample_emission would emit from `p` (normal n) along `dir`.
void emission_pdf(const Light &light, Vec3 p, Vec3 n, Vec3 dir, float scene_radius, float &pdf_pos, float &pdf_dir);
// True if the light's position is a delta (point and spot without radius) or its
// direction is (sun without angle): such a light vertex cannot be hit or connected to
// as a surface.
bool light_is_delta_position(const Light &light);
bool light_is_delta_direction(const Light &light);

}  // namespace rdv
