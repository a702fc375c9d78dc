#include "media/medium_stack.h"
#include "core/ray_offset.h"

namespace rdv {

MediumStack MediumStack::from(const std::vector<int> &media) {
  MediumStack s;
  for (int m : media)
    if (s.n_ < int(s.media_.size())) s.media_[s.n_++] = int16_t(m);
  return s;
}

void MediumStack::cross(const Scene &scene, uint32_t material, Vec3 ng, Vec3 d) {
  int m = scene.interior_medium(material);
  if (m < 0) return;
  if (dot(d, ng) < 0) {  // entering (the geometric normal points out of a closed mesh)
    if (n_ < int(media_.size())) media_[n_++] = int16_t(m);
  } else {
    // Leaving: remove the innermost entry of this medium (media may overlap imperfectly).
    for (int i = n_ - 1; i >= 0; --i)
      if (media_[i] == m) {
        for (int k = i; k < n_ - 1; ++k) media_[k] = media_[k + 1];
        --n_;
        break;
      }
  }
}

Color medium_transmittance(const Scene &scene, const ShadowRay &ray, MediumStack stack, uint64_t &rays, SampleRun &rng,
                           int transparent_layers, MediumStack *end, uint32_t mask, bool plain_layers_only) {
  Color tr(1.0f);
  const Vec3 d = ray.d;
  Vec3 o = ray.o;
  float remaining = ray.tmax;
  for (int guard = 0; guard < 64 + transparent_layers; ++guard) {
    SurfaceHit hit;
    CoincidentBoundary boundary;
    ++rays;
    bool found = scene.intersect_media(Ray{o, d, remaining, mask}, hit, boundary);
    float seg = found ? hit.t : remaining;
    int m = stack.current(scene);
    if (m >= 0) {
      tr *= scene.medium(m).transmittance(o, d, seg, rng);
      if (is_black(tr)) return tr;
    }
    if (!found) {
      if (end) *end = stack;
      return tr;
    }
    if (!scene.is_boundary_only(hit.material)) {
      // A real surface blocks, unless it is partly transparent (transparent shadows).
      const Material &mat = scene.material(hit.material);
      if (transparent_layers-- <= 0 || !mat.transparent || (plain_layers_only && !scene.is_plain_layer(hit)))
        return Color(0.0f);
      tr *= mat.shadow_transmission(scene.shading_point(hit));
      if (is_black(tr)) return tr;
    }
    stack.cross(scene, hit, boundary, d);
    o = spawn_origin(hit.p, hit.ng, hit.error, d);
    if (!std::isinf(remaining)) remaining -= hit.t;
    if (remaining <= 0) {
      if (end) *end = stack;
      return tr;
    }
  }
  return Color(0.0f);
}

}  // namespace rdv
