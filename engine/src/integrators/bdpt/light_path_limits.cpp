// Cycles' Light Paths in BDPT (integrators/light_path_limits.h): each strategy (s, t)
// classifies the whole path it makes, camera vertices c1 .. c(t-1) then light vertices
// l(s-1) .. l1 toward the light l0, so every strategy keeps or drops the same paths as
// the path tracer. The walks record each vertex's kind, the running bounce counts and
// the caustics check of their own pairs; a connection adds its two vertices.
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

bool Bdpt::record_kind(PathVertex *path, int n, Vec3 wi, bool camera, bool delta) const {
  const LightPathLimits &limits = settings_.limits;
  PathVertex &v = path[n];
  v.kind = kind_toward(v, wi);
  v.counts = BounceCounts{};
  v.caustics_ok = true;
  if (n >= 2) {
    const PathVertex &prev = path[n - 1];
    v.counts = prev.counts;
    // On a light subpath the camera side of a pair is the later vertex.
    v.caustics_ok = prev.caustics_ok && (camera ? limits.caustic_allowed(prev.kind, v.kind)
                                                : limits.caustic_allowed(v.kind, prev.kind));
  }
  // Cycles' defensive sampling: at a camera path's first scattering with no pass before it.
  if (camera || n >= 2) v.counts.add(v.kind, glossy_odds_toward(v, wi, camera, delta, camera && n == 1 && v.passes == 0));
  return v.caustics_ok && limits.within(v.counts);
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

float Bdpt::limits_share(const PathVertex *light_path, const PathVertex *camera_path, int s, int t,
                         ScatterKind kc, ScatterKind kl, Vec3 to_light) const {
  const LightPathLimits &limits = settings_.limits;
  BounceCounts counts;  // over every scattering vertex but the last
  bool ok = true;
  if (s == 0) {  // c1 .. c(t-2), then the emitter c(t-1): c(t-2) is the last
    const int last = t - 2;
    if (last >= 2) counts = camera_path[last - 1].counts;
    if (last >= 1) ok = camera_path[last].caustics_ok;
    return ok ? limits.kept_share(counts) : 0.0f;
  }
  // A connection vertex's glossy odds matter only where the path's reflections could number
  // more than the smaller of the diffuse and glossy limits (else every assignment of its mixed
  // reflections is kept): short paths skip that pass over the vertex's lobes (-1: counted
  // by its dominant kind, which keeps them within both limits).
  const int light_reflections = s - 2 >= 1 ? light_path[s - 2].counts.reflections() : 0;
  auto odds_matter = [&]() {
    return counts.reflections() + light_reflections + 2 > std::min(limits.diffuse, limits.glossy);
  };
  if (t >= 2) {
    const int m = t - 1;  // the camera vertex of the connection
    if (m >= 2) {
      counts = camera_path[m - 1].counts;
      ok = camera_path[m - 1].caustics_ok && limits.caustic_allowed(camera_path[m - 1].kind, kc);
    }
    if (s == 1) return ok ? limits.kept_share(counts) : 0.0f;  // c(t-1) meets the light: the last
    const PathVertex &c = camera_path[m];
    counts.add(kc, odds_matter() ? glossy_odds_toward(c, to_light, true, false, m == 1 && c.passes == 0) : -1.0f);
    ok = ok && limits.caustic_allowed(kc, kl);
  }
  if (s - 1 >= 2) {  // l1 is the last scattering vertex: never counted
    // With t = 1 the light vertex is the camera's first scattering (defensive sampling).
    const PathVertex &l = light_path[s - 1];
    counts.add(kl, odds_matter() ? glossy_odds_toward(l, -to_light, false, false, t == 1) : -1.0f);
  }
  if (s - 2 >= 1) {
    const PathVertex &l = light_path[s - 2];
    ok = ok && l.caustics_ok && limits.caustic_allowed(kl, l.kind);
    counts = counts + l.counts;
  }
  return ok ? limits.kept_share(counts) : 0.0f;
}

}  // namespace rdv::bdpt
