// Cycles' light passes for BDPT (film/light_passes.h): every strategy (s, t) classifies
// the whole path it makes, camera vertices c1 .. c(t-1) then light vertices l(s-1) .. l1,
// by its first scattering vertex from the camera (vertices passed straight through do
// not count) and by how many scattering vertices it has, so the passes of all
// strategies, light tracing's splats included, add up to the image.
#include "integrators/bdpt/bdpt.h"

namespace rdv::bdpt {

// From path[i] toward path[i + 1] on the same subpath.
static Vec3 direction_to_next(const PathVertex *path, int i) {
  const PathVertex &next = path[i + 1];
  return next.infinite ? next.dir : normalize(next.p - path[i].p);
}

KindSplit Bdpt::split_at(const PathVertex &v, Vec3 toward_camera, Vec3 toward_light, bool delta) {
  if (v.type == VertexType::Medium) return KindSplit::only(3);
  return v.bsdf.kind_split(toward_camera, toward_light, delta);
}

Bdpt::PassCache Bdpt::pass_cache(const PathVertex *camera_path, int n) const {
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

Bdpt::PassClass Bdpt::pass_class(const PathVertex *light_path, const PathVertex *camera_path, int s, int t,
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

void Bdpt::add_color_passes(const PathVertex *camera_path, int n, LightPassSample &passes) const {
  // Every layer the camera sees up to the first that scatters, by what reaches it.
  for (int i = 1; i < n; ++i) {
    const PathVertex &v = camera_path[i];
    if (v.type != VertexType::Surface) break;
    Color colors[kColorKinds];
    v.bsdf.kind_colors(v.wo, colors);
    for (int k = 0; k < kColorKinds; ++k) passes.color[k] += v.beta * colors[k];
    if (!v.passed_through) break;
  }
}

void Bdpt::add_light_pass(const PathVertex *camera_path, int s, int t, const PassClass &pc, Color c,
                          LightPassSample &passes) const {
  if (pc.scatterings == 0 && s == 0 && camera_path[t - 1].infinite) {
    const Color background = c * background_share(camera_path[t - 1]);  // the world seen directly
    passes.add(background, 0, pc.first, true);
    passes.add(c - background, 0, pc.first);
  } else {
    passes.add(c, pc.scatterings, pc.first);
  }
}

Color Bdpt::background_share(const PathVertex &v) const {
  const bool transparent_world = v.see_through && settings_.alpha.film_transparent;
  Color background(0.0f), all(0.0f);
  for (uint32_t li : scene_.infinite_lights()) {
    const Light &light = scene_.lights()[li];
    if (!light.visible_camera() || (transparent_world && light.type == LightType::Background)) continue;
    const Color Le = infinite_light_radiance(light, v.dir);
    all += Le;
    if (light.type == LightType::Background) background += Le;
  }
  Color share(0.0f);
  for (int c = 0; c < 3; ++c) share[c] = all[c] > 0 ? background[c] / all[c] : 0.0f;
  return share;
}

}  // namespace rdv::bdpt
