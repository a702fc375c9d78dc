// Participating media behind one interface: free-flight distance sampling,
// transmittance, the phase function, absorption / scattering / emission, all RGB.
// Chromatic media sample a distance with one colour channel chosen uniformly and
// weight with the one-sample MIS (balance heuristic) over the channels, so every
// channel stays unbiased. A scene without media never calls any of this.
//
// Homogeneous media are closed-form. Grid media (density_grid.h) scale the
// coefficients by a voxel density and are sampled by delta / ratio tracking
// (grid_tracking.cpp, unbiased) or by Pauly et al.'s random-offset ray marching
// (ray_marching.cpp, approximate). Every estimator draws from a SampleRun (the
// sampler's dimensions reserved for it on the path, then a generator seeded by them),
// so a render stays a function of the sampler's numbers while tracking takes as many
// as it needs.
#pragma once
#include <memory>
#include <string>
#include <vector>
#include "core/hash.h"
#include "core/params.h"
#include "media/blackbody.h"
#include "media/density_grid.h"
#include "media/grid_buffers.h"
#include "media/phase.h"
#include "samplers/sample_run.h"

namespace rdv {

enum class MediumType : uint8_t { Homogeneous, GridTracking, GridRayMarching };

struct MediumSample {
  bool scattered = false;  // true: a scattering event at t; false: the ray reached tmax
  float t = 0;
  Color weight{1.0f};      // sigma_s Tr / pdf (scattered) or Tr / P(no event) (reached tmax)
};

struct Medium {
  std::string name;
  MediumType type = MediumType::Homogeneous;
  // Homogeneous: the coefficients. Grid: per unit of voxel density (times "density").
  Color sigma_a{0.0f}, sigma_s{0.0f}, sigma_t{0.0f};
  // Emission, radiance per unit length, independent of density (as in Cycles):
  // `emission` (colour x strength) times the `emission_grid` value where there is one,
  // plus blackbody emission at `temperature` times the `temperature_grid` value.
  Color emission{0.0f};
  Blackbody blackbody;
  float temperature = 1000;
  std::shared_ptr<const DensityGrid> emission_grid, temperature_grid;
  HenyeyGreenstein phase;
  std::shared_ptr<const DensityGrid> grid;  // grid media only
  // Set by the scene when the medium is a volume light (a bounded emissive medium that
  // light subpaths and next-event estimation sample): its light, and the spacing of
  // the points at which camera paths gather its emission (media/emission_gather.h).
  int light = -1;
  float emission_step = 0;
  Vec3 light_lo{0.0f}, light_hi{0.0f};  // the world box the light emits from
  float step_size = 0;                      // ray marching: world units
  // Problems found while loading (a missing VDB file): the scene warns with them. A
  // grid that cannot be loaded leaves an empty medium (vacuum): the render goes on
  // without it, its boundary invisible.
  std::vector<std::string> warnings;

  // From Cycles-style parameters: {"density", "color" (scattering albedo),
  // "absorption_color", "anisotropy", "emission_color", "emission_strength"} or the
  // physical {"sigma_a", "sigma_s", "emission", "anisotropy"}; plus an optional "grid"
  // (dense values or a VDB file, see docs/scene-format.md) with "method" and "step_size".
  // A grid {"buffer": name} reads the dense grid of that name from `buffers`.
  static Medium from_params(Params &p, const std::string &name, const GridBuffers *buffers = nullptr);

  // sigma_s / sigma_t per channel (0 where nothing attenuates): the denoising albedo of a
  // scattering in it (film/denoising_passes.h).
  Color scattering_albedo() const {
    return {sigma_t.x > 0 ? sigma_s.x / sigma_t.x : 0.0f, sigma_t.y > 0 ? sigma_s.y / sigma_t.y : 0.0f,
            sigma_t.z > 0 ? sigma_s.z / sigma_t.z : 0.0f};
  }
  bool is_emissive() const { return !is_black(emission) || blackbody.active(); }
  // Emission at a world point (inside the medium).
  Color emission_at(Vec3 p) const {
    Color e = emission;
    if (emission_grid && !is_black(e)) e *= emission_grid->density(emission_grid->world_to_grid().point(p));
    if (blackbody.active()) {
      float T = temperature;
      if (temperature_grid) T *= temperature_grid->density(temperature_grid->world_to_grid().point(p));
      e += blackbody.radiance(T);
    }
    return e;
  }
  // The part of the emission that is the same everywhere in the medium.
  Color uniform_emission() const {
    Color e = emission_grid ? Color(0.0f) : emission;
    if (blackbody.active() && !temperature_grid) e += blackbody.radiance(temperature);
    return e;
  }
  // The grid whose voxels shape the emission (the emission grid, else the temperature
  // grid), or null: volume lights sample by its voxels and gather at its voxel size.
  std::shared_ptr<const DensityGrid> emission_shape() const {
    if (emission_grid && !is_black(emission)) return emission_grid;
    return blackbody.active() ? temperature_grid : nullptr;
  }
  bool has_emission_grids() const { return emission_shape() != nullptr; }
  bool is_heterogeneous() const { return type != MediumType::Homogeneous; }

  // Closed-form transmittance of a homogeneous medium over a distance (may be infinite).
  Color transmittance(float distance) const {
    if (std::isinf(distance)) return {sigma_t.x > 0 ? 0.0f : 1.0f, sigma_t.y > 0 ? 0.0f : 1.0f, sigma_t.z > 0 ? 0.0f : 1.0f};
    return {std::exp(-sigma_t.x * distance), std::exp(-sigma_t.y * distance), std::exp(-sigma_t.z * distance)};
  }
  // Transmittance from o along unit d over `distance`; grid media estimate it with
  // random numbers from rng (ratio tracking: unbiased; ray marching: approximate).
  Color transmittance(Vec3 o, Vec3 d, float distance, SampleRun &rng) const {
    switch (type) {
      case MediumType::Homogeneous: return transmittance(distance);
      case MediumType::GridTracking: return ratio_tracking(o, d, distance, rng);
      case MediumType::GridRayMarching: return ray_marched_transmittance(o, d, distance, rng);
    }
    return Color(0.0f);
  }
  // A free-flight distance from o along unit d, up to tmax (may be infinite), with
  // random numbers from rng (homogeneous: channel and distance, the first two).
  // A medium that does not scatter is attenuated instead (never a scattering event).
  MediumSample sample_distance(Vec3 o, Vec3 d, float tmax, SampleRun &rng) const {
    switch (type) {
      case MediumType::Homogeneous: return sample_homogeneous(tmax, rng);
      case MediumType::GridTracking: return delta_tracking(o, d, tmax, rng);
      case MediumType::GridRayMarching: return ray_marched_distance(o, d, tmax, rng);
    }
    return {};
  }

 private:
  // A dense or VDB grid (see from_params); null, with a warning in m that the render
  // goes on `without` something, if it cannot be read.
  static std::shared_ptr<const DensityGrid> load_grid(Medium &m, const nlohmann::json &grid, const std::string &what,
                                                      const std::string &without, const GridBuffers *buffers);
  MediumSample sample_homogeneous(float tmax, SampleRun &rng) const;
  MediumSample delta_tracking(Vec3 o, Vec3 d, float tmax, SampleRun &rng) const;
  Color ratio_tracking(Vec3 o, Vec3 d, float distance, SampleRun &rng) const;
  MediumSample ray_marched_distance(Vec3 o, Vec3 d, float tmax, SampleRun &rng) const;
  Color ray_marched_transmittance(Vec3 o, Vec3 d, float distance, SampleRun &rng) const;
};

}  // namespace rdv
