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
// The blurred BSDF at a vertex is a function of the path's camera-side prefix (its camera-
// side densities), so the path's contribution f is one function however the path was
// sampled, and BDPT (with pssmlt and mmlt, which sample its strategies) estimates the
// same image as the path tracer (docs/bdpt.md, Filter Glossy):
//  - camera subpaths sample and evaluate the blurred BSDF, as the path tracer does;
//  - light subpaths sample the unblurred BSDF, which is the path's BSDF wherever the blur
//    leaves it unchanged; a strategy whose light walk sampled a direction at a vertex the
//    blur changes (by that path's camera-side densities) cannot make the path: it adds
//    nothing, and the MIS weights of every strategy leave it out (a property of the path,
//    so the weights still sum to one); the light vertex a strategy connects at is
//    evaluated with its blurred BSDF. Strategies that sample from the camera side (s = 0,
//    next-event estimation, and every connection nearer the light than the blurred
//    vertices) always remain.
// Path-space mlt uses the same rule (mlt/path_space.h): f blurs each surface by its path's
// camera-side prefix, the camera side samples the blurred BSDF, the light side the unblurred
// one with density 0 where the blur changes it.
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
  float alpha() const { return alpha_after(min_pdf); }
  // The same for a path whose smallest density so far is min_density.
  float alpha_after(float min_density) const {
    const float p = min_density * inv_blur;
    return p < 1 ? 0.5f * std::sqrt(1.0f - p) : 0.0f;
  }
};

}  // namespace rdv
