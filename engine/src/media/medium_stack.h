// Which medium a path is in: a small stack, so media may nest (fog in a glass of
// smoke in a foggy room). Entering a closed mesh whose material has a volume pushes
// that medium; leaving it pops it. The world's medium lies under everything.
#pragma once
#include <array>
#include "core/ray_offset.h"
#include "scene/scene.h"

namespace rdv {

struct RayStats;

class MediumStack {
 public:
  static MediumStack for_camera(const Scene &scene) { return from(scene.camera_media()); }
  static MediumStack from(const std::vector<int> &outermost_first);
  int current(const Scene &scene) const { return n_ > 0 ? media_[n_ - 1] : scene.world_medium(); }
  // The path crosses the surface of `hit` travelling along d, and the medium boundary
  // lying in it if there is one (Scene::intersect_media).
  void cross(const Scene &scene, const SurfaceHit &hit, const CoincidentBoundary &boundary, Vec3 d) {
    cross(scene, hit.material, hit.ng, d, boundary);
  }
  void cross(const Scene &scene, uint32_t material, Vec3 ng, Vec3 d, const CoincidentBoundary &boundary) {
    cross(scene, material, ng, d);
    if (boundary.material >= 0) cross(scene, uint32_t(boundary.material), boundary.ng, d);
  }
  void cross(const Scene &scene, uint32_t material, Vec3 ng, Vec3 d);

 private:
  std::array<int16_t, 8> media_{};
  int n_ = 0;
};

// Transmittance from p along unit d over `distance` (infinite: to the world), through
// index-matched boundaries and the media between them; 0 if any real surface blocks.
// ng: geometric normal at p (zero for points in a medium), to leave the surface.
// transparent_layers: up to this many partly transparent surfaces tint instead of
// blocking (the path tracer's transparent shadows, within Transparent max bounces; 0:
// every surface blocks, as in BDPT, which makes such surfaces path vertices instead).
// rng: the random numbers of grid media's transmittance estimators (the connection's
// own dimensions, samplers/dimension_layout.h). end, if given, receives the media at
// the far end (a volume light's point emits only inside its medium). mask: the kinds of
// ray it stands for (scene/ray_visibility.h): surfaces invisible to them do not block.
// plain_layers_only: of the transparent surfaces, only those BDPT's walks pass without
// making them vertices let the ray through (Scene::is_plain_layer).
Color medium_transmittance(const Scene &scene, const ShadowRay &ray, MediumStack stack, uint64_t &rays, SampleRun &rng,
                           int transparent_layers = 0, MediumStack *end = nullptr,
                           uint32_t mask = 0xffffffffu, bool plain_layers_only = false);

}  // namespace rdv
