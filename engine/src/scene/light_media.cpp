// The media each light sits in, found once per commit instead of once per BDPT light
// subpath. A point's media are constant over any connected region that no medium
// boundary passes through, so a light whose extent (padded by the ray offset) meets no
// boundary triangle's bounding box has one stack, found from its centre; any other
// light (one straddling a boundary, an emissive triangle that is itself a boundary, a
// volume light, whose medium's boundary encloses its points) keeps the per-sample walk.
#include <algorithm>
#include "core/ray_offset.h"
#include "scene/scene.h"

namespace rdv {

namespace {

struct Box {
  Vec3 lo{kInf}, hi{-kInf};
  void grow(Vec3 p) { lo = vmin(lo, p); hi = vmax(hi, p); }
  bool overlaps(const Box &b) const {
    return lo.x <= b.hi.x && b.lo.x <= hi.x && lo.y <= b.hi.y && b.lo.y <= hi.y && lo.z <= b.hi.z && b.lo.z <= hi.z;
  }
  // Grown by a margin well above the offsets rays leave surfaces by (core/ray_offset.h).
  Box padded() const {
    float m = 1e-4f * (max_component(vmax(vabs(lo), vabs(hi))) + max_component(hi - lo)) + 1e-6f;
    return {lo - Vec3(m), hi + Vec3(m)};
  }
  Vec3 centre() const { return (lo + hi) * 0.5f; }
};

// Where a light's emitting points lie (light_emission.cpp), or an empty box for lights
// whose media are not one stack (infinite and volume lights).
Box light_extent(const Light &l) {
  Box b;
  switch (l.type) {
    case LightType::Point:
    case LightType::Spot:
      b.grow(l.position - Vec3(l.radius));
      b.grow(l.position + Vec3(l.radius));
      break;
    case LightType::Area: {
      Vec3 half = (vabs(l.edge_u) + vabs(l.edge_v)) * 0.5f;
      b.grow(l.position - half);
      b.grow(l.position + half);
      break;
    }
    case LightType::Triangle:
      b.grow(l.p0);
      b.grow(l.p0 + l.edge_u);
      b.grow(l.p0 + l.edge_v);
      break;
    default:
      break;
  }
  return b;
}

// Bounding boxes of the boundary triangles (those whose material has an interior
// medium), grouped by instance so a light far from an instance skips its triangles.
struct BoundaryBoxes {
  struct Group { Box box; size_t first = 0, last = 0; };
  std::vector<Group> groups;
  std::vector<Box> triangles;
  // Box tests left before the remaining lights fall back to the per-sample walk, so
  // a scene of many emissive triangles in a finely meshed medium commits quickly.
  uint64_t budget = 20'000'000;

  // True if b surely meets no boundary; false if it may, or the budget is spent.
  bool clear(const Box &b) {
    for (const Group &g : groups) {
      if (budget == 0) return false;
      --budget;
      if (!g.box.overlaps(b)) continue;
      for (size_t i = g.first; i < g.last; ++i) {
        if (budget == 0) return false;
        --budget;
        if (triangles[i].overlaps(b)) return false;
      }
    }
    return true;
  }
};

}  // namespace

void Scene::find_light_media() {
  light_media_.assign(lights_.size(), LightMedia{});
  if (media_.empty()) return;
  BoundaryBoxes boundaries;
  for (const Instance &inst : instances_) {
    if (!inst.enabled) continue;
    const Mesh &mesh = meshes_[inst.mesh];
    BoundaryBoxes::Group group;
    group.first = boundaries.triangles.size();
    for (uint32_t t = 0; t < mesh.num_triangles(); ++t) {
      if (material_interior_[mesh.materials[t]] < 0) continue;
      Box tri;
      for (int k = 0; k < 3; ++k) tri.grow(inst.to_world.point(mesh.positions[mesh.indices[3 * t + k]]));
      boundaries.triangles.push_back(tri);
      group.box.grow(tri.lo);
      group.box.grow(tri.hi);
    }
    group.last = boundaries.triangles.size();
    if (group.last > group.first) boundaries.groups.push_back(group);
  }
  // One walk per region: the emissive triangles of an instance whose whole box meets
  // no boundary share the media found from the box's centre.
  std::vector<int> instance_state(instances_.size(), 0);  // 0 unknown, 1 clear, -1 not
  std::vector<std::vector<int>> instance_media(instances_.size());
  for (uint32_t i = 0; i < lights_.size(); ++i) {
    const Light &l = lights_[i];
    if (l.type == LightType::Triangle) {
      int &state = instance_state[l.instance];
      if (state == 0) {
        const Instance &inst = instances_[l.instance];
        const Mesh &mesh = meshes_[inst.mesh];
        Box box;
        for (uint32_t v = 0; v < mesh.num_vertices(); ++v) box.grow(inst.to_world.point(mesh.positions[v]));
        state = boundaries.clear(box.padded()) ? 1 : -1;
        if (state == 1) instance_media[l.instance] = media_along(box.centre(), l.axis);
      }
      if (state == 1) {
        light_media_[i] = {true, instance_media[l.instance]};
        continue;
      }
    }
    Box extent = light_extent(l);
    if (!(extent.lo.x <= extent.hi.x) || !boundaries.clear(extent.padded())) continue;
    light_media_[i] = {true, media_along(extent.centre(), l.axis)};
  }
}

}  // namespace rdv
