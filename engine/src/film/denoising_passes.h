// Cycles 3.4's denoising data (kernel/film/denoising_passes.h): Denoising Normal, Albedo
// and Depth, the feature images Blender's Denoise node (OpenImageDenoise) takes.
//
// They are not the first hit's: a camera sample follows its path through near-specular
// surfaces (mirrors, smooth glass, Transparent BSDF) to the first one rough enough, as
// Cycles does:
// - at each surface, the closures are split by roughness: alpha_x * alpha_y > 0.075^2
//   (diffuse-like lobes count as rough) or near-specular;
// - if more than 25% of the closures' sample weight is rough (or there is no closure),
//   the features are written there: Normal = the shading normal in camera space (x
//   right, y up, z along the view: a surface facing the camera has z < 0), Albedo =
//   throughput x the rough closures' summed albedo; then the sample writes no more;
// - else throughput *= the near-specular closures' summed albedo and the path goes on
//   wherever it scatters (a glass ball shows the refracted or reflected surface, by its
//   Fresnel, as the path picks them);
// - Depth: every surface on the way adds average(throughput) x the length of the ray
//   segment that reached it (the first from the near clip plane), so a mirror's pixel
//   holds the distance to the mirror plus the reflected distance;
// - a ray segment through a medium that scatters adds beta x throughput x the medium's
//   single-scattering albedo x (1 - the segment's transmittance) to Albedo, whether the
//   path scatters on it or goes on (beta: the path's own throughput; Cycles' volume
//   integration in kernel/integrator/shade_volume.h: its ray marching accumulates albedo x
//   (1 - transmittance) step by step, a homogeneous segment in one step, and the expected
//   value of a heterogeneous segment's sum is the same); a scattering on it ends the
//   features with Normal (0, 0, -1);
// - emission the path finds on the way (emitters, lamps, the world, seen directly or through
//   the near-specular surfaces) adds throughput x its contribution to Albedo, as Cycles;
// - what the path never writes stays 0 (Normal and Depth where the world is seen).
// The pixel holds the mean over its samples (the normal is not renormalised, as Cycles).
#pragma once
#include <array>
#include "core/math.h"

namespace rdv {

// Cycles' threshold on alpha_x * alpha_y (bsdf_get_specular_roughness_squared).
inline constexpr float kDenoisingRoughness2 = 0.075f * 0.075f;

// The closures of one surface as the features see them (Bsdf::denoising_closures).
struct DenoisingClosures {
  Color rough_albedo{0.0f}, specular_albedo{0.0f};
  float weight = 0, rough_weight = 0;  // sample weights: all closures', the rough ones'
  Vec3 normal{0.0f};                   // world-space shading normal, on the viewer's side
};

// The camera's axes for the features' normal (Cycles' camera space: +z forward).
struct CameraAxes {
  Vec3 right{1, 0, 0}, up{0, 1, 0}, forward{0, 0, -1};
  Vec3 to_camera(Vec3 n) const { return {dot(n, right), dot(n, up), dot(n, forward)}; }
};

// One camera sample's features, gathered along its path (FirstHit::data.denoising).
struct DenoisingSample {
  bool active = false;  // still looking for the surface to write at (set when the film keeps them)
  Color throughput{1.0f};
  Vec3 normal{0.0f};
  Color albedo{0.0f};
  float depth = 0;

  // A surface the path reached after a ray segment of length `segment`.
  void add_surface(const DenoisingClosures &c, float segment, const CameraAxes &camera) {
    depth += average(throughput) * segment;
    if (c.weight == 0 || c.rough_weight * 4.0f > c.weight) {
      normal = camera.to_camera(c.normal);
      albedo += throughput * c.rough_albedo;  // after what media and emission on the way added
      active = false;
    } else {
      throughput *= c.specular_albedo;
    }
  }
  // Emission the path finds (an emitter, a lamp, the world; MIS-weighted as the image
  // has it) while the features are active: Cycles adds it to the albedo too
  // (film_write_emission_or_background_pass), so the world seen directly or in a mirror
  // shows its colour there.
  void add_emission(Color contribution) { albedo += throughput * contribution; }
  // A ray segment through a medium of single-scattering albedo `medium_albedo` and
  // transmittance `transmittance` (over the whole segment, to the surface or boundary that
  // ends it), entered with path throughput beta.
  void add_volume_segment(Color beta, Color medium_albedo, Color transmittance) {
    albedo += throughput * beta * medium_albedo * (Color(1.0f) - transmittance);
  }
  // A scattering in a volume: Cycles takes it as diffuse enough to end the features, with
  // the view direction as Normal.
  void end_at_volume_scatter() {
    normal = Vec3(0, 0, -1);
    active = false;
  }
};

// A pixel's sums of them (double: render parts merge to the whole render's).
struct DenoisingSums {
  std::array<double, 3> normal{}, albedo{};
  double depth = 0;
  void add(const DenoisingSample &s) {
    for (int c = 0; c < 3; ++c) {
      normal[c] += s.normal[c];
      albedo[c] += s.albedo[c];
    }
    depth += s.depth;
  }
};

}  // namespace rdv
