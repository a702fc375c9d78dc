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

void Bdpt::add_color_passes(const DataPassSample &data, LightPassSample &passes) {
  // Every layer the camera sees up to the first that scatters, by what reaches it (the
  // camera walk gathers them: the plain layers it passes are no vertices).
  for (int k = 0; k < kColorKinds; ++k) passes.color[k] += data.colors[k];
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
