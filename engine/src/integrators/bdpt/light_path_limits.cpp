// Cycles' Light Paths in BDPT (integrators/light_path_limits.h): each strategy (s, t)
// classifies the whole path it makes, camera vertices c1 .. c(t-1) then light vertices
// l(s-1) .. l1 toward the light l0, so every strategy keeps or drops the same paths as
// the path tracer. The walks record each vertex's kind, the running bounce counts and
// the caustics switches' chain (caustics_switches.h: a camera walk its state past each
// vertex, a light walk the rest of the path toward the light); a connection adds its two
// vertices.
#include "integrators/bdpt/bdpt.h"

namespace rdv::bdpt {

ScatterKind Bdpt::kind_toward(const PathVertex &v, Vec3 wi) const {
  return v.type == VertexType::Medium ? ScatterKind::Volume : v.bsdf.scatter_kind(v.wo, wi);
}

float Bdpt::glossy_odds_toward(const PathVertex &v, Vec3 w, bool camera, bool delta, bool defensive) const {
  if (v.type != VertexType::Surface) return -1;
  // The pair's camera-side direction first: a camera vertex's wo, a light vertex's w.
  return camera ? v.bsdf.glossy_odds(v.wo, w, delta, defensive) : v.bsdf.glossy_odds(w, v.wo, delta, defensive);
}

CausticStep Bdpt::caustic_step_toward(const PathVertex &v, Vec3 w, bool camera, bool delta, ScatterKind kind,
                                      float glossy_odds, bool after_diffuse) const {
  if (v.type != VertexType::Surface) return caustic_step(settings_.limits, kind, -1, Color(1.0f));
  // The pair's camera-side direction first: a camera vertex's wo, a light vertex's w.
  return camera ? caustic_step(settings_.limits, v.bsdf, v.wo, w, delta, kind, glossy_odds, after_diffuse)
                : caustic_step(settings_.limits, v.bsdf, w, v.wo, delta, kind, glossy_odds, after_diffuse);
}

bool Bdpt::record_kind(PathVertex *path, int n, Vec3 wi, bool camera, bool delta) const {
  const LightPathLimits &limits = settings_.limits;
  PathVertex &v = path[n];
  v.kind = kind_toward(v, wi);
  v.counts = n >= 2 ? path[n - 1].counts : BounceCounts{};
  // l1 is always a path's last scattering vertex: neither counted nor labelled.
  const bool labelled = camera || n >= 2;
  // Cycles' defensive sampling: at a camera path's first scattering with no pass before it.
  const float glossy = labelled ? glossy_odds_toward(v, wi, camera, delta, camera && n == 1 && v.passes == 0) : -1.0f;
  if (labelled) v.counts.add(v.kind, glossy);
  if (limits.caustics) {
    if (camera) {
      const CausticState before = n >= 2 ? path[n - 1].caustics : CausticState{};
      const CausticStep step = caustic_step_toward(v, wi, true, delta, v.kind, glossy, !is_black(before.diffuse));
      v.caustic_kept = step.kept;
      v.caustics = before.after(step);
    } else {
      const CausticStep step = caustic_step_toward(v, wi, false, delta, v.kind, glossy);
      v.caustics = n >= 2 ? path[n - 1].caustics.before(step) : CausticState::last(step.kept);
    }
    if (v.caustics.none()) return false;
  }
  return limits.within(v.counts);
}

int Bdpt::path_passes(const PathVertex *light_path, const PathVertex *camera_path, int s, int t) {
  return camera_path[t - 1].passes + (s >= 2 ? light_path[s - 1].passes : 0);
}

int Bdpt::path_scatterings(const PathVertex *light_path, const PathVertex *camera_path, int s, int t) {
  if (s == 0) return camera_path[t - 1].scatterings;  // camera_path[t - 1] is the emitter
  // The connection's ends scatter: camera_path[t - 1] (not the camera itself) and light_path[s - 1]
  // (not the light itself).
  return camera_path[t - 1].scatterings + (t >= 2 ? 1 : 0) + (s >= 2 ? light_path[s - 1].scatterings + 1 : 0);
}

Color Bdpt::limits_share(const PathVertex *light_path, const PathVertex *camera_path, int s, int t,
                         ScatterKind kc, ScatterKind kl, Vec3 to_light) const {
  const LightPathLimits &limits = settings_.limits;
  BounceCounts counts;  // over every scattering vertex but the last
  // The caustics switches: the camera side's state entering the next vertex (past camera
  // vertex m; the camera's own: nothing before it), and the rest of the path on the light side.
  auto camera_state = [&](int m) { return m >= 1 ? camera_path[m].caustics : CausticState{}; };
  CausticState state, rest;
  if (s == 0) {  // c1 .. c(t-2), then the emitter c(t-1): c(t-2) is the last
    const int last = t - 2;
    if (last >= 2) counts = camera_path[last - 1].counts;
    const Color share(limits.kept_share(counts));
    if (!limits.caustics || last < 1) return share;
    return share * camera_state(last - 1).at_last(camera_path[last].caustic_kept);
  }
  // A connection vertex's glossy odds matter only where the path's reflections could number
  // more than the smaller of the diffuse and glossy limits (else every assignment of its mixed
  // reflections is kept), or where the caustics switches act: short paths skip that pass over
  // the vertex's lobes (-1: counted by its dominant kind, which keeps them within both limits).
  const int light_reflections = s - 2 >= 1 ? light_path[s - 2].counts.reflections() : 0;
  auto odds_matter = [&]() {
    return counts.reflections() + light_reflections + 2 > std::min(limits.diffuse, limits.glossy);
  };
  if (t >= 2) {
    const int m = t - 1;  // the camera vertex of the connection
    if (m >= 2) counts = camera_path[m - 1].counts;
    state = camera_state(m - 1);
    const PathVertex &c = camera_path[m];
    if (s == 1) {  // c(t-1) meets the light: the last
      const Color share(limits.kept_share(counts));
      if (!limits.caustics) return share;
      const CausticStep step = caustic_step_toward(c, to_light, true, false, kc, -1, !is_black(state.diffuse));
      return share * state.at_last(step.kept);
    }
    const bool counted = odds_matter();
    const bool defensive = m == 1 && c.passes == 0;
    const float glossy = counted || limits.caustics ? glossy_odds_toward(c, to_light, true, false, defensive) : -1.0f;
    counts.add(kc, counted ? glossy : -1.0f);
    if (limits.caustics)
      state = state.after(caustic_step_toward(c, to_light, true, false, kc, glossy, !is_black(state.diffuse)));
  }
  // With t = 1 the light vertex is the camera's first scattering (defensive sampling).
  const PathVertex &l = light_path[s - 1];
  const bool counted = s - 1 >= 2 && odds_matter();  // l1 is the last scattering vertex: never counted
  const bool labelled = s - 1 >= 2 && (counted || limits.caustics);
  const float glossy = labelled ? glossy_odds_toward(l, -to_light, false, false, t == 1) : -1.0f;
  if (s - 1 >= 2) counts.add(kl, counted ? glossy : -1.0f);
  if (limits.caustics) {
    const CausticStep step = caustic_step_toward(l, -to_light, false, false, kl, glossy, !is_black(state.diffuse));
    rest = s - 1 >= 2 ? light_path[s - 2].caustics.before(step) : CausticState::last(step.kept);
  }
  if (s - 2 >= 1) counts = counts + light_path[s - 2].counts;
  const Color share(limits.kept_share(counts));
  return limits.caustics ? share * state.meet(rest) : share;
}

}  // namespace rdv::bdpt
