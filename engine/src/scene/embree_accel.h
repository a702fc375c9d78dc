// The only user of Embree: one BVH per mesh, and a top-level BVH of instances, so a
// mesh placed 1,000 times is stored once. Moving an instance rebuilds only the top level.
// Triangles that are index-matched medium boundaries (materials of "type": "volume")
// go into BVHs of their own, queried separately (Scene::intersect), so that a boundary
// lying in the plane of a real surface never hides it; a scene without such boundaries
// has one BVH and one query per ray, as before.
#pragma once
#include <embree3/rtcore.h>
#include <atomic>
#include <vector>
#include "core/math.h"
#include "scene/mesh.h"
#include "scene/motion.h"
#include "scene/ray_visibility.h"

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
  // boundary_material[m] != 0: triangles of material m are medium boundaries.
  void build(const std::vector<Mesh> &meshes, const std::vector<Instance> &instances,
             const std::vector<uint8_t> &boundary_material);
  void mark_instances_dirty() { top_dirty_ = true; }
  // The mesh's geometry was replaced: rebuild its BVH (and the top level) at the next build().
  void mark_mesh_dirty(uint32_t mesh) { dirty_meshes_.push_back(mesh); top_dirty_ = true; }

  // Real surfaces only.
  bool intersect(const Ray &ray, RawHit &hit) const { return intersect(top_, ray, hit); }
  // mask: the kinds of ray (scene/ray_visibility.h) the query stands for.
  bool occluded(Vec3 o, Vec3 d, float tmax, uint32_t mask) const;
  // One mesh's real surfaces alone, the ray in its object space (Cycles' local intersection:
  // what else lies there, even on the same spot, neither hides them nor is met).
  bool intersect_mesh(uint32_t mesh, const Ray &object_ray, RawHit &hit) const {
    const RTCScene surfaces = mesh < mesh_scenes_.size() ? mesh_scenes_[mesh].surfaces : nullptr;
    return surfaces && intersect(surfaces, object_ray, hit);
  }
  // Medium boundaries only.
  bool has_boundaries() const { return boundary_top_ != nullptr; }
  // Medium boundaries only, met by rays of every kind (a ray that passes a volume's
  // object still enters and leaves its medium).
  bool intersect_boundary(const Ray &ray, RawHit &hit) const {
    Ray any = ray;
    any.mask = visibility::kAnyRay;
    return intersect(boundary_top_, any, hit);
  }
  size_t memory_bytes() const { return memory_.load(); }
  // Some instance moves (Instance::moving) or deforms (Mesh::deforming): rays carry the sample's shutter time
  // (scene/motion.h). Without, every ray's time is 0 and Embree ignores it.
  bool has_motion() const { return has_motion_; }

 private:
  static bool memory_monitor(void *user, ssize_t bytes, bool post);
  bool intersect(RTCScene scene, const Ray &ray, RawHit &hit) const;
  // Rays Embree can take in world space and in every instance's object space (it aborts
  // on others); a ray beyond them meets nothing (see embree_accel.cpp).
  struct RayRange { float origin, direction; };
  RayRange range_{0, 0};  // set by build(); nothing is traced before it
  bool has_motion_ = false;
  float ray_time() const { return has_motion_ ? shutter::now() : 0.0f; }
  void update_ray_range(const std::vector<Instance> &instances);
  bool can_trace(Vec3 o, Vec3 d, float tfar) const;
  // A mesh's two BVHs: its real surfaces and its medium boundaries (either may be null).
  struct MeshScenes {
    RTCScene surfaces = nullptr, boundaries = nullptr;
  };
  MeshScenes mesh_scenes(const Mesh &m, const std::vector<uint8_t> &boundary_material) const;
  static void release(MeshScenes &s);
  RTCDevice device_ = nullptr;
  RTCScene top_ = nullptr, boundary_top_ = nullptr;
  std::vector<MeshScenes> mesh_scenes_;
  bool top_dirty_ = true;
  std::vector<uint32_t> dirty_meshes_;
  std::atomic<ssize_t> memory_{0};
};

}  // namespace rdv
