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
// camera side drops the path (caustics_switches.h: for mixtures, the share Cycles drops).
// Clamps act on each contribution (sum of its RGB, as Cycles): direct = paths with at most
// one scattering vertex.
#pragma once
#include <algorithm>
#include <cstdint>
#include "bsdfs/scatter_kind.h"
#include "core/math.h"

namespace rdv {

// Bounces of each counted kind so far (diffuse, glossy, transmission, volume).
// A reflection off a mixture of diffuse and glossy closures (a Principled BSDF) is one or
// the other in Cycles by the closure it sampled: as a function of the path, a diffuse
// bounce with odds 1 - g and a glossy one with odds g (Bsdf::glossy_odds). Such mixed
// reflections are counted apart: their number and the distribution of how many of them
// were diffuse, so the limits keep the share of the path Cycles keeps (kept_share).
struct BounceCounts {
  // Distributions are kept up to this many diffuse reflections among the mixed ones;
  // more are lumped into the last entry (exact up to 15 mixed reflections, beyond Cycles'
  // default of 12 bounces in all; smaller than 31 for BDPT's vertices, which carry them).
  static constexpr int kMaxMixedDiffuse = 15;
  uint16_t n[4] = {0, 0, 0, 0};  // scatterings of one kind (and mixed ones: in `mixed`)
  uint16_t mixed = 0;
  // diffuse_of_mixed[j]: the odds that j of the mixed reflections were diffuse (only the
  // first min(mixed, kMaxMixedDiffuse) + 1 entries are meaningful; none while mixed is 0).
  float diffuse_of_mixed[kMaxMixedDiffuse + 1];

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
  // Diffuse, glossy and mixed reflections: an upper bound on either kind's count.
  int reflections() const { return n[0] + n[1] + mixed; }
  // A scattering of kind k whose glossy odds are g (Bsdf::glossy_odds; < 0 or k not a
  // reflection: k alone decides).
  void add(ScatterKind k, float g) {
    if ((k != ScatterKind::Diffuse && k != ScatterKind::Glossy) || g < 0) return add(k);
    if (g <= 0) return add(ScatterKind::Diffuse);
    if (g >= 1) return add(ScatterKind::Glossy);
    if (mixed == 0) diffuse_of_mixed[0] = 1;
    const int top = std::min<int>(mixed, kMaxMixedDiffuse);
    if (top < kMaxMixedDiffuse) diffuse_of_mixed[top + 1] = diffuse_of_mixed[top] * (1 - g);
    else diffuse_of_mixed[top] += diffuse_of_mixed[top - 1] * (1 - g);  // the lump keeps its mass
    for (int j = std::min(top, kMaxMixedDiffuse - 1); j >= 1; --j)
      diffuse_of_mixed[j] = diffuse_of_mixed[j] * g + diffuse_of_mixed[j - 1] * (1 - g);
    diffuse_of_mixed[0] *= g;
    ++mixed;
  }
  BounceCounts operator+(const BounceCounts &o) const {
    BounceCounts c;
    for (int i = 0; i < 4; ++i) c.n[i] = uint16_t(n[i] + o.n[i]);
    if (mixed == 0 && o.mixed == 0) return c;
    if (o.mixed == 0) return c.with_mixed_of(*this);
    if (mixed == 0) return c.with_mixed_of(o);
    c.mixed = uint16_t(mixed + o.mixed);
    const int ta = std::min<int>(mixed, kMaxMixedDiffuse), tb = std::min<int>(o.mixed, kMaxMixedDiffuse);
    const int tc = std::min<int>(c.mixed, kMaxMixedDiffuse);
    for (int j = 0; j <= tc; ++j) c.diffuse_of_mixed[j] = 0;
    for (int a = 0; a <= ta; ++a)
      for (int b = 0; b <= tb; ++b)
        c.diffuse_of_mixed[std::min(a + b, kMaxMixedDiffuse)] += diffuse_of_mixed[a] * o.diffuse_of_mixed[b];
    return c;
  }

 private:
  BounceCounts with_mixed_of(const BounceCounts &o) {
    mixed = o.mixed;
    const int top = std::min<int>(mixed, kMaxMixedDiffuse);
    for (int j = 0; j <= top; ++j) diffuse_of_mixed[j] = o.diffuse_of_mixed[j];
    return *this;
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
  // (a scene that uses none of these renders exactly as without them), and whether a
  // caustics switch is off (caustics_switches.h weighs each path then).
  bool classify = false, clamps = false, caustics = false;

  void finish() {
    caustics = !caustics_reflective || !caustics_refractive;
    classify = diffuse < kNoLimit || glossy < kNoLimit || transmission < kNoLimit || volume < kNoLimit || caustics;
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
  // The share of paths with these counts that the limits keep: 0 or 1, or with mixed
  // reflections the odds that as many of them were diffuse as the diffuse and glossy
  // limits both allow.
  float kept_share(const BounceCounts &c) const {
    if (c.n[2] > transmission || c.n[3] > volume || c.n[0] > diffuse || c.n[1] > glossy) return 0;
    if (c.mixed == 0) return 1;
    // j diffuse among the m mixed: n0 + j <= diffuse and n1 + m - j <= glossy.
    const int m = c.mixed, top = std::min(m, BounceCounts::kMaxMixedDiffuse);
    const int lo = std::max(0, m - (glossy - c.n[1])), hi = std::min(top, diffuse - c.n[0]);
    float kept = 0;
    for (int j = lo; j <= hi; ++j) kept += c.diffuse_of_mixed[j];
    return std::min(kept, 1.0f);
  }
  bool within(const BounceCounts &c) const { return kept_share(c) > 0; }
  // A contribution of a path with `scattering_vertices` scattering vertices, clamped.
  Color clamp(Color c, int scattering_vertices) const {
    float limit = scattering_vertices <= 1 ? clamp_direct : clamp_indirect;
    if (!(limit > 0)) return c;
    float sum = c.x + c.y + c.z;
    return sum > limit ? c * (limit / sum) : c;
  }
};

}  // namespace rdv
