// The only user of Embree: one BVH per mesh, and a top-level BVH of instances, so a
// mesh placed 1,000 times is stored once. Moving an instance rebuilds only the top level.
#pragma once
#include <embree3/rtcore.h>
#include <atomic>
#include <vector>
#include "core/math.h"
#include "scene/mesh.h"

namespace rdv {

struct RawHit {
  float t;
  float u, v;        // barycentrics of vertices 1 and 2
  uint32_t instance;
  uint32_t prim;
};

class EmbreeAccel {
 public:
  EmbreeAccel();
  ~EmbreeAccel();
  EmbreeAccel(const EmbreeAccel &) = delete;
  EmbreeAccel &operator=(const EmbreeAccel &) = delete;

  // Builds what changed: mesh BVHs for meshes not built yet, then the top level.
  void build(const std::vector<Mesh> &meshes, const std::vector<Instance> &instances);
  void mark_instances_dirty() { top_dirty_ = true; }
  // The mesh's geometry was replaced: rebuild its BVH (and the top level) at the next build().
  void mark_mesh_dirty(uint32_t mesh) { dirty_meshes_.push_back(mesh); top_dirty_ = true; }

  bool intersect(const Ray &ray, RawHit &hit) const;
  bool occluded(Vec3 o, Vec3 d, float tmax) const;
  size_t memory_bytes() const { return memory_.load(); }

 private:
  static bool memory_monitor(void *user, ssize_t bytes, bool post);
  RTCDevice device_ = nullptr;
  RTCScene top_ = nullptr;
  std::vector<RTCScene> mesh_scenes_;
  bool top_dirty_ = true;
  std::vector<uint32_t> dirty_meshes_;
  std::atomic<ssize_t> memory_{0};
};

}  // namespace rdv
