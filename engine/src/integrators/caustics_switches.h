// Cycles' caustics switches (Light Paths > Caustics: Reflective, Refractive) as a function
// of the path, so that every integrator and every BDPT strategy weighs a path alike.
//
// Cycles 3.4 builds a surface's closures knowing whether the ray that reached it left a
// diffuse bounce (PATH_RAY_DIFFUSE: the closure sampled there was diffuse or translucent).
// If it did, a switch that is off leaves out the surface's glossy reflection closures
// (Reflective) or its refracting ones (Refractive): a Principled BSDF keeps only its diffuse
// part there. Which closure a bounce sampled is a matter of odds for a mixture (the diffuse
// closures' share of the density of the direction taken, Bsdf::glossy_odds), so the weight
// Cycles gives a path on average is an expectation over those labels: a chain of two states
// along the path from the camera, "the bounce before was diffuse" or not. Each vertex keeps
// its whole f in the first state and the share the switches keep (Bsdf::caustic_share, per
// colour channel) in the second, and passes to the next vertex in either state by its odds.
// For BSDFs of one kind this is the plain rule (a glossy reflection or a refraction right
// after a diffuse bounce drops the path); for mixtures it is exact where the bounce limits
// do not bind. Under both, the limits still count a mixed reflection by its unfiltered odds
// (BounceCounts), independent of the state (README).
//
// A camera subpath carries the state's two weights past each vertex (after); a light
// subpath carries the weight of the rest of the path toward the light given the state in
// which a path enters the vertex (before); a connection meets the two (meet).
#pragma once
#include "bsdfs/bsdf.h"
#include "bsdfs/scatter_kind.h"
#include "core/math.h"
#include "integrators/light_path_limits.h"

namespace rdv {

// One scattering vertex in the chain.
struct CausticStep {
  Color kept = Color(1.0f);  // the share of f the switches keep after a diffuse bounce
  float diffuse = 0;         // the odds the vertex's bounce is diffuse with all its closures
  float diffuse_kept = 1;    // the same after a diffuse bounce (switched-off closures gone)
};

struct CausticState {
  // Camera side: the weight of the label histories whose last bounce was not diffuse /
  // was. Light side: the weight of the rest of the path entered in either state.
  Color other = Color(1.0f), diffuse = Color(0.0f);

  bool none() const { return is_black(other) && is_black(diffuse); }
  // The camera-side state past vertex v.
  CausticState after(const CausticStep &v) const {
    return {other * (1 - v.diffuse) + diffuse * v.kept * (1 - v.diffuse_kept),
            other * v.diffuse + diffuse * v.kept * v.diffuse_kept};
  }
  // The rest of the path from vertex v on, given this rest past v (light side).
  CausticState before(const CausticStep &v) const {
    return {other * (1 - v.diffuse) + diffuse * v.diffuse,
            v.kept * (other * (1 - v.diffuse_kept) + diffuse * v.diffuse_kept)};
  }
  // The rest of a path whose last scattering vertex keeps `kept` (its bounce meets the light).
  static CausticState last(Color kept) { return {Color(1.0f), kept}; }
  // The path's weight: this camera-side state entering what `rest` stands for.
  Color meet(const CausticState &rest) const { return other * rest.other + diffuse * rest.diffuse; }
  // The weight of a path whose last scattering vertex keeps `kept`.
  Color at_last(Color kept) const { return other + diffuse * kept; }
};

// The step of a vertex of this kind (Bsdf::scatter_kind), with Cycles' glossy odds for a
// reflection (Bsdf::glossy_odds; < 0: the kind decides) and the share the switches keep
// (Bsdf::caustic_share; asked only where a switch acts on that side: caustic_share_needed).
// A volume scattering is not a diffuse bounce and keeps all; a straight pass changes nothing.
inline CausticStep caustic_step(const LightPathLimits &limits, ScatterKind kind, float glossy_odds, Color kept) {
  CausticStep s;
  s.kept = kept;
  switch (kind) {
    case ScatterKind::Diffuse:
    case ScatterKind::Glossy:
      s.diffuse = glossy_odds >= 0 ? 1 - glossy_odds : kind == ScatterKind::Diffuse ? 1.0f : 0.0f;
      s.diffuse_kept = limits.caustics_reflective ? s.diffuse : 1.0f;  // only diffuse closures left
      break;
    case ScatterKind::Translucent: s.diffuse = s.diffuse_kept = 1; break;
    case ScatterKind::Transmission: s.diffuse_kept = limits.caustics_refractive ? 0.0f : 1.0f; break;
    case ScatterKind::Volume: s.diffuse_kept = 0; break;
    case ScatterKind::Transparent: break;
  }
  return s;
}

// Whether a vertex of this kind needs its BSDF's caustic_share (else it keeps everything).
inline bool caustic_share_needed(const LightPathLimits &limits, ScatterKind kind) {
  switch (kind) {
    case ScatterKind::Diffuse:
    case ScatterKind::Glossy: return !limits.caustics_reflective;
    case ScatterKind::Translucent:
    case ScatterKind::Transmission: return !limits.caustics_refractive;
    case ScatterKind::Volume:
    case ScatterKind::Transparent: return false;
  }
  return false;
}

// The step of a surface vertex scattering from camera_side to light_side (delta: by a delta
// lobe), of kind `kind` with glossy odds `glossy_odds`. after_diffuse: whether a path may
// reach it after a diffuse bounce (a camera side's state with a diffuse weight; unknown on a
// light subpath); where not, its kept share weighs nothing and is not computed.
inline CausticStep caustic_step(const LightPathLimits &limits, const Bsdf &bsdf, Vec3 camera_side, Vec3 light_side,
                                bool delta, ScatterKind kind, float glossy_odds, bool after_diffuse = true) {
  const Color kept = after_diffuse && caustic_share_needed(limits, kind)
                         ? bsdf.caustic_share(camera_side, light_side, delta, limits.caustics_reflective,
                                              limits.caustics_refractive)
                         : Color(1.0f);
  return caustic_step(limits, kind, glossy_odds, kept);
}

}  // namespace rdv
