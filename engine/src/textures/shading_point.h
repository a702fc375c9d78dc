// What textures see of a surface point: positions in world / object / generated
// space, the default UV map, named mesh attributes (UV maps, vertex colours), the
// tangent frame (dp/du, dp/dv) that normal maps and bump need, and the ray's
// footprint there (dx, dy) that image lookups filter over.
#pragma once
#include <cstdint>
#include <string>
#include "core/math.h"

namespace rdv {

struct Mesh;
class TextureRays;

// A value of the object itself that an Attribute node of type Object or Instancer reads
// (Blender's custom property or RNA path, looked up by the add-on per instance), as RGBA: a
// number n as (n, n, n, 1), shorter arrays after (0, 0, 0, 1).
struct ObjectAttribute {
  uint32_t id;  // attribute_id of the name (Instancer lookups: of kInstancerPrefix + name)
  float value[4];
};
constexpr const char *kInstancerPrefix = "\x1finstancer:";

struct ShadingPoint {
  Vec3 p{0.0f};          // world position
  Vec3 ng{0, 0, 1};      // geometric normal (front side), world
  Vec3 ns{0, 0, 1};      // interpolated shading normal, world
  Vec2 uv;               // default (active render) UV map; barycentrics when the mesh has none
  Vec3 p_object{0.0f};   // object-space position (Texture Coordinate: Object)
  Vec3 generated{0.0f};  // position in the mesh's bounding box, 0..1 (Generated)
  Vec3 dpdu{1, 0, 0}, dpdv{0, 1, 0};  // world-space derivatives along the default UV map
  Vec3 dpdu_object{1, 0, 0}, dpdv_object{0, 1, 0};  // the same in object space
  Vec3 generated_scale{1.0f};          // d(generated) / d(object position)
  bool has_uv_frame = false;           // dpdu/dpdv come from real UVs
  // The ray's footprint on the surface: its two axes as steps in (u, v) along dpdu /
  // dpdv (one pixel apart for camera rays; zero: a point, unfiltered lookups).
  Vec2 dx{0.0f, 0.0f}, dy{0.0f, 0.0f};
  // Object Info: the instance's random number, colour, alpha and pass index, the material's
  // pass index (scene/mesh.h Instance); location from object_to_world.
  float object_random = 0, object_alpha = 1, object_index = 0, material_index = 0;
  Color object_color{1.0f};
  const Mesh *mesh = nullptr;          // for named attributes
  const ObjectAttribute *object_attributes = nullptr;  // the instance's (Attribute: Object / Instancer)
  uint32_t num_object_attributes = 0;
  // The Ambient Occlusion and Bevel nodes' rays (textures/texture_rays.h): the scene that
  // traces them (null: none; AO 1, Bevel the shading normal), the point's rounding error (for
  // their origin) and its instance.
  const TextureRays *rays = nullptr;
  Vec3 error{0.0f};
  uint32_t instance = 0;
  // The ray that reached the point came from behind the surface (against ng): Cycles turns
  // its normal toward that ray (a room's walls seen from inside), which the AO node follows.
  bool backfacing = false;
  // How far the light a surface emits here travels to the point it reaches (Cycles' ray
  // length, read by Light Falloff): the segment to the camera or to the point being lit. An
  // emitter's value evaluated without one (power estimates) is the value at 1; infinite: a
  // sun's or the world's distance, where Light Falloff is its Strength.
  float ray_length = 1;
  uint32_t v[3] = {0, 0, 0};           // triangle vertex indices
  float b[3] = {1, 0, 0};              // barycentrics
  // Row-major 3x4 object-to-world transform (at the sample's shutter time for a moving
  // object), for object-space normal maps; has_object_to_world false: none (identity).
  float object_to_world[12] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};
  bool has_object_to_world = false;

  // Interpolated attribute (id from attribute_id()); false if the mesh lacks it.
  bool attribute(uint32_t id, float out[4], int &components) const;
  // The instance's attribute `id`; false (and zeros, as Cycles) when the object has none.
  bool object_attribute(uint32_t id, float out[4]) const;
  bool has_footprint() const { return dx.x != 0 || dx.y != 0 || dy.x != 0 || dy.y != 0; }
  // The point moved along the surface by duv (in the dpdu / dpdv parameters): for
  // finite differences (bump, footprints of mapped coordinates). Named attributes
  // stay those of this point.
  ShadingPoint shifted(Vec2 duv) const {
    ShadingPoint s = *this;
    s.uv = {uv.x + duv.x, uv.y + duv.y};
    s.p = p + dpdu * duv.x + dpdv * duv.y;
    Vec3 d_object = dpdu_object * duv.x + dpdv_object * duv.y;
    s.p_object = p_object + d_object;
    s.generated = generated + d_object * generated_scale;
    return s;
  }
};

// Process-wide ids for attribute names ("UVMap.001", "Col"), so lookups compare integers.
uint32_t attribute_id(const std::string &name);

}  // namespace rdv
