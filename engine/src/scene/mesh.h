// A triangle mesh as the engine keeps it: stored once, placed by any number of instances.
#pragma once
#include <string>
#include <vector>
#include "core/math.h"
#include "textures/shading_point.h"

namespace rdv {

// A named per-vertex attribute: a UV map (2 components) or a colour (3 or 4).
struct MeshAttribute {
  uint32_t id = 0;  // attribute_id(name) (textures/shading_point.h)
  std::string name;
  int components = 0;
  std::vector<float> data;  // components per vertex
};

struct Mesh {
  std::string name;
  // positions has one padding element past the end: Embree reads vertices with
  // 16-byte loads and shares this buffer instead of copying it.
  std::vector<Vec3> positions;
  std::vector<Vec3> normals;   // empty: flat shading
  std::vector<Vec2> uvs;       // empty: no UVs
  std::vector<uint32_t> indices;  // 3 per triangle
  std::vector<uint32_t> materials;  // 1 per triangle (scene material id)
  std::vector<MeshAttribute> attributes;  // named UV maps and vertex colours
  Vec3 bbox_lo{0.0f}, bbox_hi{1.0f};     // object space, for generated coordinates
  // Index of each triangle among this mesh's emissive triangles, or kNotEmissive.
  std::vector<uint32_t> emissive_rank;
  uint32_t num_emissive = 0;
  static constexpr uint32_t kNotEmissive = 0xffffffffu;
  // Deformation motion blur (scene/motion.h): the vertex positions at n >= 2 evenly
  // spaced times over the open shutter (each with the padding element, as positions,
  // for Embree's vertex buffer of that time step), or empty; normal_steps: the vertex
  // normals at the same times (unit or zero), or empty (then `normals` at every time).
  // `deforming` (derived by Scene::commit): steps given, the shutter open, and not an
  // emitter or a medium boundary. positions stays the mesh at its frame: lights,
  // bounds and everything outside a sample use it.
  std::vector<std::vector<Vec3>> position_steps, normal_steps;
  bool deforming = false;
  // True displacement (scene/displacement.cpp): while a material moves the vertices, the
  // positions, their steps and the normals as given, to start from when it is redone;
  // displacement_key: what the mesh was displaced by (0: not displaced).
  std::vector<Vec3> given_positions, given_normals;
  std::vector<std::vector<Vec3>> given_position_steps, given_normal_steps;
  uint64_t displacement_key = 0;

  uint32_t num_vertices() const { return static_cast<uint32_t>(positions.size() - 1); }
  uint32_t num_triangles() const { return static_cast<uint32_t>(indices.size() / 3); }
  size_t memory_bytes() const {
    size_t steps = 0;
    for (const auto &v : position_steps) steps += v.capacity() * sizeof(Vec3);
    for (const auto &v : normal_steps) steps += v.capacity() * sizeof(Vec3);
    for (const auto &v : given_position_steps) steps += v.capacity() * sizeof(Vec3);
    for (const auto &v : given_normal_steps) steps += v.capacity() * sizeof(Vec3);
    steps += (given_positions.capacity() + given_normals.capacity()) * sizeof(Vec3);
    return steps + positions.capacity() * sizeof(Vec3) + normals.capacity() * sizeof(Vec3) +
           uvs.capacity() * sizeof(Vec2) + (indices.capacity() + materials.capacity() + emissive_rank.capacity()) * 4 +
           attribute_bytes();
  }
  size_t attribute_bytes() const {
    size_t b = 0;
    for (const MeshAttribute &a : attributes) b += a.data.capacity() * sizeof(float);
    return b;
  }
};

// Where an instance is: its transform, the inverse, and how they carry rounding errors
// (core/ray_offset.h): |M| and |M| |M^-1|. A moving instance's at a shutter time:
// Scene::placement_now.
struct InstancePlacement {
  Transform to_world;
  Transform to_object;
  Transform abs_linear, error_mixing;
  // All four from to_world, which must be invertible.
  static InstancePlacement of(const Transform &to_world);
};

struct Instance : InstancePlacement {
  uint32_t mesh = 0;
  uint32_t light_base = 0;  // first emissive-triangle light of this instance
  bool enabled = true;      // false for a zero-scale transform: not rendered
  // Object > Visibility > Holdout: a hole in the alpha where the camera sees it, and
  // nothing else there; shaded as usual for every other ray (integrators/film_alpha.h).
  bool holdout = false;
  // Object > Visibility > Shadow Catcher (integrators/path/shadow_catcher.h): the camera
  // paths that meet it first split into the image with everything and the catcher's
  // own pass, whose rays meet shadow catchers only.
  bool shadow_catcher = false;
  // Object > Visibility > Ray Visibility: the kinds of ray that see it (scene/ray_visibility.h).
  uint32_t visibility = 63;
  // One of an object's copies on the same spot, each a look of its material for some kinds
  // of ray (Light Path's ray types: the exporter's "look_copy"). BDPT's light walks end on
  // one of mixed visibility (integrators/bdpt/bdpt.h).
  bool look_copy = false;
  // Motion blur (scene/motion.h): to_world at n >= 2 evenly spaced times over the open
  // shutter, or empty. `moving` (derived by Scene::commit) says whether the instance is
  // rendered moving: steps given, the shutter open, and not a light or medium boundary.
  std::vector<Transform> motion;
  bool moving = false;
  // Object > Relations > Pass Index (the Object Index pass, film/data_passes.h).
  float pass_index = 0;
  // What an Object Info node reads: Blender's per-instance random number (the depsgraph's
  // random_id / (2^32 - 1), as Cycles) and the object's Viewport Display colour and alpha.
  float random = 0;
  Color color{1.0f};
  float alpha = 1;
  // What Attribute nodes of type Object / Instancer read (textures/shading_point.h).
  std::vector<ObjectAttribute> attributes;
  // Cryptomatte (film/cryptomatte.h): the names of the object and of its asset (topmost
  // parent), as indices into the scene's names (Scene::crypto_name); both the mesh's by default.
  uint32_t crypto_object = 0, crypto_asset = 0;
};

}  // namespace rdv
