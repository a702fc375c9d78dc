// Cycles' Light Paths settings (Render Properties > Light Paths): bounce limits per kind
// of scattering, the caustics switches, and the clamps of direct and indirect light.
// Every integrator applies them to whole paths, so each BDPT strategy (light subpaths
// included) keeps or drops the same paths as the path tracer does.
//
// How Cycles counts (kernel/integrator/path_state.h, with the +1 of scene/integrator.cpp):
// a path camera -> x1 -> ... -> xm -> emitter is kept when, over x1 .. x(m-1) (every
// scattering vertex but the one that meets the light), the number of diffuse reflections,
// glossy reflections, transmissions and volume scatterings each stays within its limit:
// diffuse bounces 0 still gives direct diffuse light. With a caustics switch off, a glossy
// reflection (reflective) or a refraction (refractive) right after a diffuse bounce on the
// camera side drops the path. Clamps act on each contribution (sum of its RGB, as Cycles):
// direct = paths with at most one scattering vertex.
#pragma once
#include <cstdint>
#include "bsdfs/scatter_kind.h"
#include "core/math.h"

namespace rdv {

// Bounces of each counted kind so far (diffuse, glossy, transmission, volume).
struct BounceCounts {
  uint16_t n[4] = {0, 0, 0, 0};

  void add(ScatterKind k) {
    switch (k) {
      case ScatterKind::Diffuse: ++n[0]; break;
      case ScatterKind::Glossy: ++n[1]; break;
      case ScatterKind::Transmission:
      case ScatterKind::Translucent: ++n[2]; break;
      case ScatterKind::Volume: ++n[3]; break;
      case ScatterKind::Transparent: break;
    }
  }
  BounceCounts operator+(const BounceCounts &o) const {
    BounceCounts c;
    for (int i = 0; i < 4; ++i) c.n[i] = uint16_t(n[i] + o.n[i]);
    return c;
  }
};

struct LightPathLimits {
  static constexpr int kNoLimit = 1 << 15;
  // Bounces of each kind before a path's last scattering vertex (Cycles' numbers).
  int diffuse = kNoLimit, glossy = kNoLimit, transmission = kNoLimit, volume = kNoLimit;
  bool caustics_reflective = true, caustics_refractive = true;
  // Cap on the RGB sum of one contribution (0 = off): direct = at most one scattering
  // vertex on the path, indirect = the rest.
  float clamp_direct = 0, clamp_indirect = 0;
  // Cycles' Transparent max bounces M: straight passes through Transparent BSDFs (and
  // alpha) a path may make. Cycles 3.4 (with the +1 of scene/integrator.cpp) lets a vertex
  // with c <= M passes behind it scatter, stops a path on the surface after its (M+1)-th
  // pass (its emission still counts) and blocks a shadow ray from a vertex with c passes
  // through k more when c + k > M. As a function of the whole path: at most M passes if
  // anything on it scatters, else M + 1 (an emitter or the world seen straight through
  // M + 1 layers still shows). Where Cycles finds an emitter by scattering through M + 1
  // passes it keeps the BSDF sample's MIS share, which no function of the path can: we
  // drop it, as its next-event estimation does (small lamps: all of it; the world: a part).
  int transparent = kNoLimit;
  // Filter Glossy (scene.cycles.blur_glossy; 0 = off): glossy lobes after unlikely
  // bounces are roughened (filter_glossy.h): every integrator, one image for all their
  // strategies (path-space mlt: a function of each path's camera-side prefix).
  float filter_glossy = 0;
  // Set by finish(): whether paths must be classified / contributions clamped at all
  // (a scene that uses none of these renders exactly as without them).
  bool classify = false, clamps = false;

  void finish() {
    classify = diffuse < kNoLimit || glossy < kNoLimit || transmission < kNoLimit || volume < kNoLimit ||
               !caustics_reflective || !caustics_refractive;
    clamps = clamp_direct > 0 || clamp_indirect > 0;
  }
  // Whether a path that passes through `passes` transparent layers in all, and has a
  // scattering vertex or not, is within Transparent max bounces.
  bool transparent_within(int passes, bool scatters) const { return passes <= transparent + (scatters ? 0 : 1); }
  // The layers a shadow ray or connection from a path with `passes` behind it may pass:
  // what the limit leaves, or `unlimited` without one.
  int layers_left(int passes, int unlimited) const {
    return transparent < kNoLimit ? (passes < transparent ? transparent - passes : 0) : unlimited;
  }
  bool within(const BounceCounts &c) const {
    return c.n[0] <= diffuse && c.n[1] <= glossy && c.n[2] <= transmission && c.n[3] <= volume;
  }
  // Whether `next` may follow `before` (its neighbour on the camera side) with the
  // caustics switches as they are.
  bool caustic_allowed(ScatterKind before, ScatterKind next) const {
    if (before != ScatterKind::Diffuse && before != ScatterKind::Translucent) return true;
    if (next == ScatterKind::Glossy) return caustics_reflective;
    if (next == ScatterKind::Transmission) return caustics_refractive;
    return true;
  }
  // A contribution of a path with `scattering_vertices` scattering vertices, clamped.
  Color clamp(Color c, int scattering_vertices) const {
    float limit = scattering_vertices <= 1 ? clamp_direct : clamp_indirect;
    if (!(limit > 0)) return c;
    float sum = c.x + c.y + c.z;
    return sum > limit ? c * (limit / sum) : c;
  }
};

}  // namespace rdv
