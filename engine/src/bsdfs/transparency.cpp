#include "bsdfs/transparency.h"
#include "core/ray_offset.h"

namespace rdv {

Color transparent_shadow(const Scene &scene, Vec3 o, Vec3 d, float tmax, uint64_t &rays, uint32_t mask,
                         int max_layers, bool plain_layers_only) {
  Color tr(1.0f);
  for (int layer = 0; layer <= max_layers; ++layer) {
    Ray ray{o, d, tmax, mask};
    SurfaceHit hit;
    ++rays;
    if (!scene.intersect(ray, hit) || !(hit.t < tmax)) return tr;
    const Material &m = scene.material(hit.material);
    if (!m.transparent || (plain_layers_only && !scene.is_plain_layer(hit))) return Color(0.0f);
    tr *= m.shadow_transmission(scene.shading_point(hit));
    if (is_black(tr)) return tr;
    o = spawn_origin(hit.p, hit.ng, hit.error, d);
    tmax = std::isinf(tmax) ? kInf : std::max(0.0f, tmax - hit.t);
  }
  return Color(0.0f);
}

}  // namespace rdv
