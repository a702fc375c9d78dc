// Cycles' light passes for BDPT (film/light_passes.h): every strategy (s, t) classifies
// the whole path it makes (bdpt/pass_class.h), so the passes of all strategies, light
// tracing's splats included, add up to the image; here the split of a scattering
// vertex, the colour passes and the world's share of what the camera sees.
#include "integrators/bdpt/bdpt.h"

namespace rdv::bdpt {

KindSplit Bdpt::split_at(const PathVertex &v, Vec3 toward_camera, Vec3 toward_light, bool delta) {
  if (v.type == VertexType::Medium) return KindSplit::only(3);
  return v.bsdf.kind_split(toward_camera, toward_light, delta);
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
