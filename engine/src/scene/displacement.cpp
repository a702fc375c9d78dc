// True displacement (Blender's Material > Settings > Displacement: Displacement Only and
// Displacement and Bump), as Cycles' GeometryManager::displace does it: each vertex of a
// triangle whose material has a "displacement" is moved by that graph's world-space offset,
// evaluated once per vertex at a corner of the first such triangle using it, through the
// mesh's first instance at the shutter's middle (Cycles: the first object, time 0.5), taken
// back to object space. Every offset is found before any vertex moves, so texture lookups see
// the mesh as given. A mesh shared by instances is displaced once, in object space.
// "true" then rebuilds the smooth normals of those vertices from the moved faces (the sum of
// the unit face normals, as Cycles); "both" keeps them, its bump (the material's surface
// normal) starting from the normals as given.
#include <tbb/parallel_for.h>
#include <atomic>
#include <cstring>
#include "scene/scene.h"

namespace rdv {

namespace {

uint64_t mix_key(uint64_t key, uint64_t value) {
  return (key ^ (value + 0x9e3779b97f4a7c15ull + (key << 6) + (key >> 2))) * 0xff51afd7ed558ccdull;
}

// The unit normals of the moved faces summed at their vertices, normalised: the smooth
// normals of the vertices that `moved` marks (others kept).
void rebuild_normals(const Mesh &m, const std::vector<Vec3> &positions, const std::vector<uint8_t> &moved_triangle,
                     std::vector<Vec3> &normals) {
  std::vector<Vec3> sum(normals.size(), Vec3(0.0f));
  std::vector<uint8_t> touched(normals.size(), 0);
  for (uint32_t t = 0; t < m.num_triangles(); ++t) {
    if (!moved_triangle[t]) continue;
    const uint32_t *v = &m.indices[3 * size_t(t)];
    const Vec3 n = cross(positions[v[1]] - positions[v[0]], positions[v[2]] - positions[v[0]]);
    const float len = length(n);
    const Vec3 unit = len > 0 && std::isfinite(len) ? n / len : Vec3(0.0f);
    for (int k = 0; k < 3; ++k) {
      sum[v[k]] += unit;
      touched[v[k]] = 1;
    }
  }
  for (size_t i = 0; i < normals.size(); ++i) {
    if (!touched[i]) continue;
    const float len = length(sum[i]);
    normals[i] = len > 0 && std::isfinite(len) ? sum[i] / len : Vec3(0.0f);  // zero: the face normal
  }
}

}  // namespace

void Scene::displace_meshes() {
  std::vector<int64_t> first_instance(meshes_.size(), -1);
  for (uint32_t i = 0; i < instances_.size(); ++i)
    if (instances_[i].enabled && first_instance[instances_[i].mesh] < 0) first_instance[instances_[i].mesh] = i;
  for (uint32_t id = 0; id < meshes_.size(); ++id) {
    Mesh &m = meshes_[id];
    // What the displacement depends on: the displacing materials' edits, the instance and
    // where it is, the mesh's steps (the mesh itself: set_mesh makes a new one, key 0).
    uint64_t key = 0;
    if (first_instance[id] >= 0) {
      std::vector<uint8_t> seen(materials_.size(), 0);
      for (uint32_t mat : m.materials) {
        if (seen[mat] || materials_[mat].displacement < 0) continue;
        seen[mat] = 1;
        key = mix_key(mix_key(key, mat + 1), material_edits_[mat]);
      }
    }
    if (key != 0) {
      const Instance &inst = instances_[size_t(first_instance[id])];
      key = mix_key(key, uint64_t(first_instance[id]));
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 4; ++c) {
          uint32_t bits;
          std::memcpy(&bits, &inst.to_world.m[r][c], 4);
          key = mix_key(key, bits);
        }
      key = mix_key(mix_key(key, inst.moving), m.deforming ? m.position_steps.size() : 0);
      if (key == 0) key = 1;
    }
    if (key == m.displacement_key) continue;
    restore_given_mesh(m);  // start again from the mesh as given
    m.displacement_key = key;
    accel_.mark_mesh_dirty(id);
    if (key != 0) displace_mesh(id, uint32_t(first_instance[id]));
  }
}

void Scene::restore_given_mesh(Mesh &m) {
  if (m.displacement_key == 0) return;
  m.positions = m.given_positions;
  m.normals = m.given_normals;
  m.position_steps = m.given_position_steps;
  m.normal_steps = m.given_normal_steps;
  m.given_positions.clear();
  m.given_normals.clear();
  m.given_position_steps.clear();
  m.given_normal_steps.clear();
  m.displacement_key = 0;
}

void Scene::displace_mesh(uint32_t mesh_id, uint32_t instance) {
  Mesh &m = meshes_[mesh_id];
  const uint32_t nv = m.num_vertices(), nt = m.num_triangles();
  // Each vertex is evaluated at its corner of the first displacing triangle using it.
  constexpr uint32_t kNone = 0xffffffffu;
  std::vector<uint32_t> corner(nv, kNone);
  std::vector<uint8_t> moved_triangle(nt, 0);
  bool rebuild = false;
  for (uint32_t t = 0; t < nt; ++t) {
    const Material &mat = materials_[m.materials[t]];
    if (mat.displacement < 0) continue;
    moved_triangle[t] = 1;
    rebuild = rebuild || !mat.displacement_keeps_normals;
    for (int k = 0; k < 3; ++k)
      if (corner[m.indices[3 * size_t(t) + k]] == kNone) corner[m.indices[3 * size_t(t) + k]] = 3 * t + uint32_t(k);
  }
  std::vector<Vec3> offset(nv, Vec3(0.0f));
  std::atomic<uint32_t> not_finite{0};
  tbb::parallel_for(tbb::blocked_range<uint32_t>(0, nv, 256), [&](const tbb::blocked_range<uint32_t> &range) {
    const shutter::SampleTime at_the_middle(0.5f);
    for (uint32_t v = range.begin(); v != range.end(); ++v) {
      if (corner[v] == kNone) continue;
      const uint32_t t = corner[v] / 3, k = corner[v] % 3;
      SurfaceHit hit;
      surface_at(instance, t, k == 1 ? 1.0f : 0.0f, k == 2 ? 1.0f : 0.0f, hit);
      const ShadingPoint sp = shading_point(hit, -hit.ns, 0.0f);
      const Material &mat = materials_[hit.material];
      const Instance &inst = instances_[instance];
      const InstancePlacement &at = inst.moving ? placement_now(inst) : placement(inst);
      const Vec3 d = at.to_object.vector(Vec3(mat.graph.eval(mat.displacement, sp)));
      if (is_finite(d)) offset[v] = d;
      else ++not_finite;
    }
  });
  if (not_finite)
    warn("mesh '" + m.name + "': the displacement of " + std::to_string(not_finite.load()) +
         " vertices is not finite (NaN or Inf); those vertices stay");
  m.given_positions = m.positions;
  m.given_normals = m.normals;
  m.given_position_steps = m.position_steps;
  m.given_normal_steps = m.normal_steps;
  for (uint32_t v = 0; v < nv; ++v) m.positions[v] += offset[v];
  for (std::vector<Vec3> &step : m.position_steps)
    for (uint32_t v = 0; v < nv; ++v) step[v] += offset[v];
  if (rebuild && !m.normals.empty()) {
    rebuild_normals(m, m.positions, moved_triangle, m.normals);
    for (size_t s = 0; s < m.normal_steps.size() && s < m.position_steps.size(); ++s)
      rebuild_normals(m, m.position_steps[s], moved_triangle, m.normal_steps[s]);
  }
}

}  // namespace rdv
