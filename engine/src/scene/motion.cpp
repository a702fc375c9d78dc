// Motion blur in the scene (scene/motion.h): instances' transform steps, which of them
// move, where a moving instance or camera is at a sample's shutter time.
#include <atomic>
#include <cmath>
#include "core/error.h"
#include "core/limits.h"
#include "scene/scene.h"

namespace rdv {

namespace {

// As set_instance_transform: an inverse entry above it cannot be traced.
constexpr float kMaxInverseEntry = 1e12f;

// An interpolated transform that can be inverted and traced: Embree inverts it for every
// ray at its time, so a step through zero scale would put NaNs into its traversal.
bool traceable(const Transform &t) {
  if (!t.is_finite() || !(std::fabs(t.det3()) > 1e-30f)) return false;
  Transform inv = t.inverse();
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c)
      if (!(std::fabs(inv.m[r][c]) <= kMaxInverseEntry)) return false;
  return true;
}

}  // namespace

std::string Scene::instance_name(uint32_t id) const {
  return "object '" + meshes_[instances_[id].mesh].name + "' (instance " + std::to_string(id) + ")";
}

uint64_t Scene::next_camera_generation() {
  static std::atomic<uint64_t> generation{0};
  return ++generation;
}

void Scene::set_instance_motion(uint32_t id, const std::vector<Transform> &steps) {
  if (id >= instances_.size()) fail("instance " + std::to_string(id) + ": no such instance");
  const std::string what = instance_name(id);
  if (steps.size() > kMaxMotionSteps)
    fail(what + ": " + std::to_string(steps.size()) + " motion steps; at most " + std::to_string(kMaxMotionSteps),
         RDV_ERROR_LIMIT);
  for (size_t k = 0; k < steps.size(); ++k)
    if (!steps[k].is_finite()) fail(what + ": motion step " + std::to_string(k) + " is not finite (NaN or Inf)");
  Instance &inst = instances_[id];
  inst.motion.clear();
  if (steps.size() >= 2) {
    // Between steps and at their quarter points: the determinant of a linear blend is a
    // cubic in the blend factor, so a sign change (a mirror flip) or zero shows there.
    bool ok = true;
    const float sign = steps[0].det3() > 0 ? 1.0f : -1.0f;
    for (size_t k = 0; k + 1 < steps.size() && ok; ++k)
      for (float f : {0.0f, 0.25f, 0.5f, 0.75f, 1.0f}) {
        Transform t = transform_at(steps, (float(k) + f) / float(steps.size() - 1));
        if (!traceable(t) || !(t.det3() * sign > 0)) { ok = false; break; }
      }
    if (ok) inst.motion = steps;
    else warn(what + ": its motion passes through a zero scale or a mirror flip; rendered without motion blur");
  }
  accel_.mark_instances_dirty();
  dirty_ = true;
}

void Scene::set_mesh_motion(uint32_t id, const float *positions, const float *normals, uint32_t num_vertices,
                            uint32_t num_steps) {
  if (id >= meshes_.size()) fail("mesh " + std::to_string(id) + ": no such mesh");
  Mesh &m = meshes_[id];
  const std::string what = "mesh '" + m.name + "'";
  if (num_steps > kMaxMotionSteps)
    fail(what + ": " + std::to_string(num_steps) + " deformation steps; at most " + std::to_string(kMaxMotionSteps),
         RDV_ERROR_LIMIT);
  std::vector<std::vector<Vec3>> position_steps, normal_steps;
  if (num_steps >= 2) {
    if (num_vertices != m.num_vertices())
      fail(what + ": deformation steps of " + std::to_string(num_vertices) + " vertices, but the mesh has " +
           std::to_string(m.num_vertices()));
    if (!positions) fail(what + ": deformation 'positions' is NULL");
    check_memory(what, std::to_string(num_steps) + " deformation steps of " + std::to_string(num_vertices) + " vertices",
                 double(num_steps) * double(num_vertices) * sizeof(Vec3) * (normals ? 2 : 1));
    // Validate everything before keeping anything: a rejected step leaves the mesh as it was.
    auto read = [&](const float *data, const char *kind, std::vector<std::vector<Vec3>> &out) {
      out.assign(num_steps, std::vector<Vec3>(size_t(num_vertices) + 1, Vec3(0.0f)));  // +1: Embree's padding
      for (uint32_t k = 0; k < num_steps; ++k)
        for (uint32_t i = 0; i < num_vertices; ++i) {
          const float *x = data + 3 * (size_t(k) * num_vertices + i);
          Vec3 v{x[0], x[1], x[2]};
          if (!is_finite(v))
            fail(what + ": deformation step " + std::to_string(k) + ", vertex " + std::to_string(i) + ": " + kind +
                 " is not finite (NaN or Inf)");
          out[k][i] = v;
        }
    };
    read(positions, "position", position_steps);
    if (normals) {
      read(normals, "normal", normal_steps);
      for (auto &step : normal_steps)
        for (Vec3 &n : step) {
          const float len = length(n);
          n = len > 0 ? n / len : Vec3(0.0f);  // zero: the face normal, as in make_mesh
        }
    }
  }
  restore_given_mesh(m);  // new steps: a displacement starts again from the mesh as given
  m.position_steps = std::move(position_steps);
  m.normal_steps = m.normals.empty() ? decltype(normal_steps)() : std::move(normal_steps);
  accel_.mark_mesh_dirty(id);
  dirty_ = true;
}

void Scene::triangle_now(const Mesh &m, const uint32_t *tri, Vec3 p[3]) {
  if (!m.deforming) {
    for (int k = 0; k < 3; ++k) p[k] = m.positions[tri[k]];
    return;
  }
  const StepBlend s = step_blend(m.position_steps.size(), shutter::now());
  const std::vector<Vec3> &a = m.position_steps[s.first], &b = m.position_steps[s.first + 1];
  for (int k = 0; k < 3; ++k) p[k] = blend(a[tri[k]], b[tri[k]], s.f);
}

void Scene::normals_now(const Mesh &m, const uint32_t *tri, Vec3 n[3]) {
  if (!m.deforming || m.normal_steps.empty()) {
    for (int k = 0; k < 3; ++k) n[k] = m.normals[tri[k]];
    return;
  }
  const StepBlend s = step_blend(m.normal_steps.size(), shutter::now());
  const std::vector<Vec3> &a = m.normal_steps[s.first], &b = m.normal_steps[s.first + 1];
  for (int k = 0; k < 3; ++k) n[k] = blend(a[tri[k]], b[tri[k]], s.f);
}

void Scene::find_motion() {
  moving_object_.clear();
  const bool open = camera_.shutter_is_open();
  // Deforming meshes first: an instance of one counts as moving for the ray time.
  for (uint32_t id = 0; id < meshes_.size(); ++id) {
    Mesh &m = meshes_[id];
    bool deforming = open && m.position_steps.size() >= 2;
    if (deforming) {
      // As for moving instances: the media a point is in are found where the mesh is at
      // its frame. (An emitting mesh deforms with its light: light_now.)
      bool bounds_medium = false;
      for (uint32_t mat : m.materials)
        bounds_medium = bounds_medium || material_interior_[mat] >= 0 || material_boundary_[mat];
      if (bounds_medium) {
        warn("mesh '" + m.name + "': bounds a medium; rendered without deformation blur, as it is at its frame");
        deforming = false;
      }
    }
    if (deforming != m.deforming) accel_.mark_mesh_dirty(id);  // one vertex buffer or one per step
    m.deforming = deforming;
    if (deforming && moving_object_.empty()) moving_object_ = "mesh '" + m.name + "' (deformation)";
  }
  for (uint32_t i = 0; i < instances_.size(); ++i) {
    Instance &inst = instances_[i];
    inst.moving = false;
    if (!open || !inst.enabled || inst.motion.size() < 2) continue;
    // Medium boundaries stay where "transform" puts them (the shutter's middle for
    // Blender's default Position Center): the media a point is in are found once per
    // commit, not per sample. (An emitting object moves with its light: light_now.)
    const Mesh &m = meshes_[inst.mesh];
    bool bounds_medium = false;
    for (uint32_t mat : m.materials)
      bounds_medium = bounds_medium || material_interior_[mat] >= 0 || material_boundary_[mat];
    if (bounds_medium) {
      warn(instance_name(i) + ": bounds a medium; rendered without motion blur, where its transform puts it");
      continue;
    }
    inst.moving = true;
    if (moving_object_.empty()) moving_object_ = instance_name(i);
  }
  if (moving_object_.empty() && camera_.moves()) moving_object_ = "the camera";
}

InstancePlacement Scene::placement_now(const Instance &inst) const {
  return InstancePlacement::of(transform_at(inst.motion, shutter::now()));
}

const Camera &Scene::camera_now() const {
  if (!camera_.moves()) return camera_;
  // One moved copy per thread, remade when the scene's camera or the sample's time changes.
  struct Moved {
    uint64_t generation = 0;
    float time = -1;
    Camera camera;
  };
  thread_local Moved moved;
  const float u = shutter::now();
  if (moved.generation != camera_generation_) {
    moved.camera = camera_;
    moved.generation = camera_generation_;
    moved.time = -1;
  }
  if (moved.time != u) {
    moved.camera.move_to(transform_at(camera_.motion, u));
    moved.time = u;
  }
  return moved.camera;
}

}  // namespace rdv
