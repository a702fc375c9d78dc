// How BDPT's light passes classify a strategy's path (film/light_passes.h; the rest in
// light_passes.cpp): every strategy (s, t) classifies the whole path it makes, camera
// vertices c1 .. c(t-1) then light vertices l(s-1) .. l1, by its first scattering vertex
// from the camera (vertices passed straight through do not count) and by how many
// scattering vertices it has. Inline: these run for every strategy of every sample.
#pragma once
#include "integrators/bdpt/bdpt.h"

namespace rdv::bdpt {

// From path[i] toward path[i + 1] on the same subpath.
inline Vec3 direction_to_next(const PathVertex *path, int i) {
  const PathVertex &next = path[i + 1];
  return next.infinite ? next.dir : normalize(next.p - path[i].p);
}

inline Bdpt::PassCache Bdpt::pass_cache(const PathVertex *camera_path, int n) const {
  PassCache cache;
  for (int i = 1; i + 1 < n; ++i) {
    const PathVertex &v = camera_path[i];
    if (v.type != VertexType::Surface && v.type != VertexType::Medium) break;
    if (v.passed_through) continue;
    cache.vertex = i;
    cache.split = split_at(v, v.wo, direction_to_next(camera_path, i), v.delta);
    break;
  }
  return cache;
}

inline Bdpt::PassClass Bdpt::pass_class(const PathVertex *light_path, const PathVertex *camera_path, int s, int t,
                                        Vec3 connection_dir, const PassCache &cache) const {
  PassClass c;
  // Scattering vertices: c1 .. c(last) (s = 0: c(t-1) is the emitter), then l(s-1) .. l1.
  const int last = s == 0 ? t - 2 : t - 1;
  int first_camera = -1, first_light = -1;
  for (int i = 1; i <= last; ++i) {
    if (camera_path[i].passed_through) continue;
    ++c.scatterings;
    if (first_camera < 0) first_camera = i;
  }
  for (int j = s - 1; j >= 1; --j) {
    if (light_path[j].passed_through) continue;
    ++c.scatterings;
    if (first_camera < 0 && first_light < 0) first_light = j;
  }
  if (first_camera >= 0) {
    const PathVertex &v = camera_path[first_camera];
    // On along the camera subpath, or (the connection vertex) toward the light side.
    const bool connection = s >= 1 && first_camera == t - 1;
    if (!connection && first_camera == cache.vertex) c.first = cache.split;
    else
      c.first = split_at(v, v.wo, connection ? connection_dir : direction_to_next(camera_path, first_camera),
                         connection ? false : v.delta);
  } else if (first_light >= 0) {
    const PathVertex &v = light_path[first_light];
    const bool connection = first_light == s - 1;
    const Vec3 toward_camera = !connection ? direction_to_next(light_path, first_light)
                               : t == 1    ? connection_dir
                                           : -connection_dir;
    c.first = split_at(v, toward_camera, v.wo, connection ? false : v.delta);
  }
  return c;
}

inline void Bdpt::add_light_pass(const PathVertex *camera_path, int s, int t, const PassClass &pc, Color c,
                                 LightPassSample &passes) const {
  if (pc.scatterings == 0 && s == 0 && camera_path[t - 1].infinite) {
    const Color background = c * background_share(camera_path[t - 1]);  // the world seen directly
    passes.add(background, 0, pc.first, true);
    passes.add(c - background, 0, pc.first);
  } else {
    passes.add(c, pc.scatterings, pc.first);
  }
}

}  // namespace rdv::bdpt
