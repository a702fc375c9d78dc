#include "scene/embree_accel.h"
#include <algorithm>
#include <cmath>
#include <string>
#include "core/error.h"
#include "core/log.h"

namespace rdv {

static void embree_error(void *, RTCError code, const char *message) {
  log_warning(std::string("Embree error ") + std::to_string(static_cast<int>(code)) + ": " + (message ? message : ""));
}

bool EmbreeAccel::memory_monitor(void *user, ssize_t bytes, bool) {
  static_cast<EmbreeAccel *>(user)->memory_ += bytes;
  return true;
}

EmbreeAccel::EmbreeAccel() {
  device_ = rtcNewDevice(nullptr);
  if (!device_) fail("Embree: could not create a device", RDV_ERROR_INTERNAL);
  rtcSetDeviceErrorFunction(device_, embree_error, nullptr);
  rtcSetDeviceMemoryMonitorFunction(device_, memory_monitor, this);
}

EmbreeAccel::~EmbreeAccel() {
  if (top_) rtcReleaseScene(top_);
  if (boundary_top_) rtcReleaseScene(boundary_top_);
  for (MeshScenes &s : mesh_scenes_) release(s);
  if (device_) rtcReleaseDevice(device_);
}

void EmbreeAccel::release(MeshScenes &s) {
  if (s.surfaces) rtcReleaseScene(s.surfaces);
  if (s.boundaries) rtcReleaseScene(s.boundaries);
  s = {};
}

EmbreeAccel::MeshScenes EmbreeAccel::mesh_scenes(const Mesh &m, const std::vector<uint8_t> &boundary_material) const {
  const uint32_t n = m.num_triangles();
  uint32_t num_boundaries = 0;
  for (uint32_t mat : m.materials) num_boundaries += boundary_material[mat] != 0;
  auto bvh = [&](bool boundaries) -> RTCScene {
    const uint32_t count = boundaries ? num_boundaries : n - num_boundaries;
    if (count == 0) return nullptr;
    RTCScene scene = rtcNewScene(device_);
    rtcSetSceneFlags(scene, RTC_SCENE_FLAG_ROBUST);  // no cracks between adjacent triangles
    RTCGeometry geom = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
    // Shared, not copied: Mesh::positions carries the padding Embree's SSE loads need.
    // A deforming mesh: one vertex buffer per time step (each padded the same way),
    // blended by Embree at each ray's time (scene/motion.h).
    if (m.deforming) {
      rtcSetGeometryTimeStepCount(geom, unsigned(m.position_steps.size()));
      for (unsigned k = 0; k < m.position_steps.size(); ++k)
        rtcSetSharedGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, k, RTC_FORMAT_FLOAT3, m.position_steps[k].data(), 0,
                                   sizeof(Vec3), m.num_vertices());
    } else {
      rtcSetSharedGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, m.positions.data(), 0,
                                 sizeof(Vec3), m.num_vertices());
    }
    if (count == n) {
      rtcSetSharedGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, m.indices.data(), 0,
                                 3 * sizeof(uint32_t), n);
    } else {
      // A mesh with both kinds: each BVH keeps the other kind's triangles as degenerate
      // ones (one vertex thrice, never hit), so primitive ids stay the mesh's triangle ids.
      auto *idx = static_cast<uint32_t *>(
          rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(uint32_t), n));
      for (uint32_t t = 0; t < n; ++t) {
        bool keep = (boundary_material[m.materials[t]] != 0) == boundaries;
        for (int k = 0; k < 3; ++k) idx[3 * t + k] = m.indices[3 * t + (keep ? k : 0)];
      }
    }
    rtcCommitGeometry(geom);
    rtcAttachGeometryByID(scene, geom, 0);
    rtcReleaseGeometry(geom);
    rtcCommitScene(scene);
    return scene;
  };
  return {bvh(false), bvh(true)};
}

void EmbreeAccel::build(const std::vector<Mesh> &meshes, const std::vector<Instance> &instances,
                        const std::vector<uint8_t> &boundary_material) {
  bool new_meshes = false;
  for (uint32_t id : dirty_meshes_) {  // replaced geometry (Scene::set_mesh) or materials
    if (id >= mesh_scenes_.size()) continue;  // not built yet: built below
    release(mesh_scenes_[id]);
    mesh_scenes_[id] = mesh_scenes(meshes[id], boundary_material);
    new_meshes = true;
  }
  dirty_meshes_.clear();
  while (mesh_scenes_.size() < meshes.size()) {
    mesh_scenes_.push_back(mesh_scenes(meshes[mesh_scenes_.size()], boundary_material));
    new_meshes = true;
  }
  if (!top_dirty_ && !new_meshes && top_) return;
  if (top_) rtcReleaseScene(top_);
  if (boundary_top_) rtcReleaseScene(boundary_top_);
  top_ = rtcNewScene(device_);
  update_ray_range(instances);
  boundary_top_ = nullptr;  // made only when some instance has boundaries
  has_motion_ = false;
  for (const Instance &inst : instances)
    has_motion_ = has_motion_ || (inst.enabled && (inst.moving || meshes[inst.mesh].deforming));
  auto add_instance = [&](RTCScene top, RTCScene mesh, const Instance &inst, uint32_t id) {
    RTCGeometry geom = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_INSTANCE);
    rtcSetGeometryInstancedScene(geom, mesh);
    // Our 4x4 row-major matrix starts with the 3x4 row-major block Embree wants. A moving
    // instance has one per time step over the shutter (scene/motion.h), interpolated
    // linearly by Embree at each ray's time: a motion-blur BVH node for it alone.
    if (inst.moving) {
      rtcSetGeometryTimeStepCount(geom, unsigned(inst.motion.size()));
      for (unsigned k = 0; k < inst.motion.size(); ++k)
        rtcSetGeometryTransform(geom, k, RTC_FORMAT_FLOAT3X4_ROW_MAJOR, &inst.motion[k].m[0][0]);
    } else {
      rtcSetGeometryTransform(geom, 0, RTC_FORMAT_FLOAT3X4_ROW_MAJOR, &inst.to_world.m[0][0]);
    }
    // Ray visibility (scene/ray_visibility.h) as the instance mask: a ray meets the
    // instance when its mask shares a bit with it. The bits no kind uses stay set, so
    // rays of every kind (mask all ones) meet every instance; shadow catchers carry their
    // kinds a second time for the catcher pass's rays (visibility::instance_mask). Medium
    // boundaries are met by every ray: a ray that passes a volume's object still enters
    // its medium.
    rtcSetGeometryMask(geom, top == top_ ? visibility::instance_mask(inst.visibility, inst.shadow_catcher) : 0xffffffffu);
    rtcCommitGeometry(geom);
    rtcAttachGeometryByID(top, geom, id);
    rtcReleaseGeometry(geom);
  };
  for (uint32_t i = 0; i < instances.size(); ++i) {
    const Instance &inst = instances[i];
    if (!inst.enabled) continue;
    const MeshScenes &ms = mesh_scenes_[inst.mesh];
    if (ms.surfaces) add_instance(top_, ms.surfaces, inst, i);
    if (ms.boundaries) {
      if (!boundary_top_) boundary_top_ = rtcNewScene(device_);
      add_instance(boundary_top_, ms.boundaries, inst, i);
    }
  }
  rtcCommitScene(top_);
  if (boundary_top_) rtcCommitScene(boundary_top_);
  top_dirty_ = false;
}

namespace {

// Embree checks every ray (RayK::valid), in world space and again in each instance's
// object space, and asserts, which in Debian's build aborts the whole process (Blender's
// too), when an origin or direction component is NaN or larger than its FLT_LARGE
// (1.844e18) or tfar is NaN.
constexpr float kEmbreeLarge = 1.844e18f;

float max_abs(Vec3 v) { return std::max(std::fabs(v.x), std::max(std::fabs(v.y), std::fabs(v.z))); }

}  // namespace

bool EmbreeAccel::can_trace(Vec3 o, Vec3 d, float tfar) const {
  return max_abs(o) <= range_.origin && max_abs(d) <= range_.direction && !std::isnan(tfar);
}

void EmbreeAccel::update_ray_range(const std::vector<Instance> &instances) {
  // In an instance's object space a ray is o' = L o + t, d' = L d (L, t: to_object), so
  // |o'| <= |L| |o| + |t| (max norms; |L| the largest row sum). Half of FLT_LARGE leaves
  // room for rounding. Scene::set_instance_transform keeps |L| and |t| far below it.
  range_ = RayRange{kEmbreeLarge / 2, kEmbreeLarge / 2};
  auto narrow = [&](const Transform &to_object) {
    float rows = 0;
    for (int r = 0; r < 3; ++r)
      rows = std::max(rows, std::fabs(to_object.m[r][0]) + std::fabs(to_object.m[r][1]) +
                                std::fabs(to_object.m[r][2]));
    float shift = max_abs(to_object.column(3));
    if (rows <= 1 && shift <= kEmbreeLarge / 4) return;
    range_.origin = std::min(range_.origin, (kEmbreeLarge / 2 - shift) / std::max(rows, 1.0f));
    range_.direction = std::min(range_.direction, kEmbreeLarge / 2 / std::max(rows, 1.0f));
  };
  for (const Instance &inst : instances) {
    if (!inst.enabled) continue;
    narrow(inst.to_object);
    // A moving instance: its steps and the quarter points between them (Scene checks
    // that the interpolated transforms stay invertible; scene/motion.cpp).
    if (inst.moving)
      for (size_t k = 0; k + 1 < inst.motion.size(); ++k)
        for (float f : {0.0f, 0.25f, 0.5f, 0.75f, 1.0f}) {
          Transform t = transform_at(inst.motion, (float(k) + f) / float(inst.motion.size() - 1));
          narrow(t.inverse());
        }
  }
}

bool EmbreeAccel::intersect(RTCScene scene, const Ray &ray, RawHit &hit) const {
  if (!can_trace(ray.o, ray.d, ray.tmax)) return false;  // the scene lies nowhere near it: a miss
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  RTCRayHit rh;
  rh.ray.org_x = ray.o.x; rh.ray.org_y = ray.o.y; rh.ray.org_z = ray.o.z;
  rh.ray.dir_x = ray.d.x; rh.ray.dir_y = ray.d.y; rh.ray.dir_z = ray.d.z;
  rh.ray.tnear = 0.0f;
  rh.ray.tfar = ray.tmax;
  rh.ray.mask = ray.mask;
  rh.ray.flags = 0;
  rh.ray.time = ray_time();
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(scene, &ctx, &rh);
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return false;
  hit.t = rh.ray.tfar;
  hit.u = rh.hit.u;
  hit.v = rh.hit.v;
  hit.instance = rh.hit.instID[0];
  hit.prim = rh.hit.primID;
  return true;
}

bool EmbreeAccel::occluded(Vec3 o, Vec3 d, float tmax, uint32_t mask) const {
  if (!can_trace(o, d, tmax)) return true;  // no light arrives along it
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  RTCRay r;
  r.org_x = o.x; r.org_y = o.y; r.org_z = o.z;
  r.dir_x = d.x; r.dir_y = d.y; r.dir_z = d.z;
  r.tnear = 0.0f;
  r.tfar = tmax;
  r.mask = mask;
  r.flags = 0;
  r.time = ray_time();
  rtcOccluded1(top_, &ctx, &r);
  return r.tfar < 0;  // Embree sets tfar = -inf on a hit
}

}  // namespace rdv
