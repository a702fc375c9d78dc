// Cycles' Filter Glossy (scene.cycles.blur_glossy; kernel/integrator/surface_shader.h,
// surface_shader_prepare_closures, Cycles 3.4): a camera path remembers the smallest density
// (solid angle) with which any of its scatterings sampled its direction (min_ray_pdf: a
// diffuse bounce's is at most 1 / pi; delta lobes count as certain, as Cycles' 1e6 does);
// at every later surface, p = that density / blur_glossy below 1 makes each microfacet lobe
// at least 0.5 sqrt(1 - p) rough (alpha), and perfect mirrors and smooth glass GGX lobes of
// that roughness (Bsdf::blur). So a glossy floor or a caustic seen after a diffuse bounce
// is blurred, and one seen straight or in a sharp mirror is not. It trades a bias for
// less noise from paths that are unlikely to be sampled.
//
// The blurred BSDF depends on how the path reached the vertex from the camera, so only an
// integrator that builds every path from the camera can apply it: the path tracer. BDPT's
// light subpaths (and the Metropolis integrators built on them) would sample a vertex's
// BSDF before its camera-side history exists, and their strategies would then estimate
// different images; they render unfiltered and the engine says so.
#pragma once
#include <algorithm>
#include <cmath>
#include "core/math.h"

namespace rdv {

struct FilterGlossy {
  float inv_blur = 0;   // 1 / blur_glossy; 0: off
  float min_pdf = kInf; // the path's smallest sampling density so far

  explicit FilterGlossy(float blur_glossy) : inv_blur(blur_glossy > 0 ? 1.0f / blur_glossy : 0.0f) {}
  bool on() const { return inv_blur > 0; }
  // A scattering sampled its direction with density pdf (not for delta lobes).
  void scattered(float pdf) { min_pdf = std::min(min_pdf, pdf); }
  // The roughness (alpha) every microfacet lobe at the next surface gets at least; 0: none.
  float alpha() const {
    const float p = min_pdf * inv_blur;
    return p < 1 ? 0.5f * std::sqrt(1.0f - p) : 0.0f;
  }
};

}  // namespace rdv
