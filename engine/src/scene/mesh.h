// A triangle mesh as the engine keeps it: stored once, placed by any number of instances.
#pragma once
#include <string>
#include <vector>
#include "core/math.h"

namespace rdv {

struct Mesh {
  std::string name;
  // positions has one padding element past the end: Embree reads vertices with
  // 16-byte loads and shares this buffer instead of copying it.
  std::vector<Vec3> positions;
  std::vector<Vec3> normals;   // empty: flat shading
  std::vector<Vec2> uvs;       // empty: no UVs
  std::vector<uint32_t> indices;  // 3 per triangle
  std::vector<uint32_t> materials;  // 1 per triangle (scene material id)
  // Index of each triangle among this mesh's emissive triangles, or kNotEmissive.
  std::vector<uint32_t> emissive_rank;
  uint32_t num_emissive = 0;
  static constexpr uint32_t kNotEmissive = 0xffffffffu;

  uint32_t num_vertices() const { return static_cast<uint32_t>(positions.size() - 1); }
  uint32_t num_triangles() const { return static_cast<uint32_t>(indices.size() / 3); }
  size_t memory_bytes() const {
    return positions.capacity() * sizeof(Vec3) + normals.capacity() * sizeof(Vec3) +
           uvs.capacity() * sizeof(Vec2) + (indices.capacity() + materials.capacity() + emissive_rank.capacity()) * 4;
  }
};

struct Instance {
  uint32_t mesh = 0;
  Transform to_world;
  Transform to_object;
  uint32_t light_base = 0;  // first emissive-triangle light of this instance
  bool enabled = true;      // false for a zero-scale transform: not rendered
};

}  // namespace rdv
