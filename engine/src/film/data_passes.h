// Cycles 3.4's data passes of what the camera sees (kernel/film/data_passes.h): Mist,
// Object Index and Material Index.
//
// A camera sample gathers them along its see-through chain: the surfaces its ray meets
// until it scatters (Transparent BSDF pass-throughs keep it going, and so do refractions
// Transparent Glass keeps seeing through; a scattering in a volume ends it: integrators/
// film_alpha.h's see_through, Cycles' PATH_RAY_TRANSPARENT_BACKGROUND).
// - Mist: each surface of the chain adds (1 - mist(distance)) x average(throughput x
//   alpha), alpha its opacity (1 - what passes straight through); the pixel reads
//   1 - (the sum / samples), clamped to [0, 1]. So an opaque surface at distance d gives
//   mist(d), the world gives 1, and fog or a half-transparent card in front mixes in
//   what lies behind, filtered over the pixel like the image.
// - Object / Material Index: object.pass_index / material.pass_index of the chain's first
//   surface whose alpha reaches the view layer's pass_alpha_threshold (any surface when
//   the threshold is 0); 0 for the world, and where the chain ends in a volume before such
//   a surface. Cycles writes them from the pixel's sample 0 alone, not filtered: an edge
//   pixel shows the one object its first sample hit, so the pass holds exact indices.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>
#include "core/math.h"
#include "core/params.h"
#include "film/cryptomatte.h"
#include "film/denoising_passes.h"
#include "film/light_passes.h"
#include "film/shader_aovs.h"

namespace rdv {

// World > Mist Pass (world.mist_settings): mist 0 up to `start` from the camera, rising
// to 1 at start + depth (0 everywhere but the world when depth is 0, as Cycles), shaped
// by the falloff: quadratic x^2, linear x, inverse quadratic sqrt(x).
struct MistSettings {
  enum class Falloff : uint8_t { Quadratic, Linear, InverseQuadratic };
  float start = 5, depth = 25;  // Blender's defaults
  Falloff falloff = Falloff::Quadratic;

  // distance: from the camera's position (orthographic: along its view axis).
  float factor(float distance) const {
    const float x = depth > 0 ? std::clamp((distance - start) / depth, 0.0f, 1.0f) : 0.0f;
    switch (falloff) {
      case Falloff::Quadratic: return x * x;
      case Falloff::InverseQuadratic: return std::sqrt(x);
      default: return x;
    }
  }
};

// One camera sample's data passes (FirstHit::data; the tile loop adds them to the film).
struct DataPassSample {
  float mist_cover = 0;  // sum over the chain of (1 - mist) x average(throughput x alpha)
  float object_index = 0, material_index = 0;
  bool indices_done = false;  // a surface at or above the alpha threshold set them
  // Cycles' denoising data (film/denoising_passes.h), along the camera's path through
  // near-specular surfaces (active only when the film keeps them).
  DenoisingSample denoising;
  // The colour passes (film/light_passes.h): the closures of every layer a BDPT camera walk
  // sees up to its first scattering, by what reaches them (bdpt/subpaths.cpp).
  static_assert(kColorKinds == 3);
  Color colors[kColorKinds] = {Color(0.0f), Color(0.0f), Color(0.0f)};
  // Shader AOVs (film/shader_aovs.h), when the film keeps them (Scene::add_data_passes).
  AovSample aovs;
  // Cryptomatte (film/cryptomatte.h), when the film keeps it (Scene::add_data_passes).
  CryptoSample crypto;

  // A surface of the see-through chain: its distance from the camera (MistSettings), the
  // throughput reaching it times its alpha, its alpha's average and its pass indices.
  void add_surface(const MistSettings &mist, float alpha_threshold, float distance, const Color &beta_alpha,
                   float alpha, float object, float material) {
    mist_cover += (1.0f - mist.factor(distance)) * average(beta_alpha);
    if (indices_done) return;
    object_index = object;
    material_index = material;
    indices_done = alpha_threshold <= 0 || alpha >= alpha_threshold;
  }
  // The chain reached the world without a surface at the threshold.
  void add_world() {
    if (indices_done) return;
    object_index = material_index = 0;
    indices_done = true;
  }
};

// "pass_index" of an object or material: an integer in Blender's range 0..32767 (an
// error naming the object otherwise).
inline int pass_index_of(Params &p, const std::string &what) {
  const nlohmann::json *j = p.get_json("pass_index");
  if (!j) return 0;
  if (!j->is_number_integer() || j->get<int64_t>() < 0 || j->get<int64_t>() > 32767)
    fail(what + ": 'pass_index' must be an integer in 0..32767 (Blender's range), got " + j->dump());
  return int(j->get<int64_t>());
}

}  // namespace rdv
