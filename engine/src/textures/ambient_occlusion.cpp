#include "textures/ambient_occlusion.h"
#include <bit>
#include <cmath>
#include "core/hash.h"
#include "core/sampling.h"
#include "textures/shading_point.h"

namespace rdv {

float ambient_occlusion(const ShadingPoint &sp, Vec3 n, float distance, int samples, bool only_local) {
  if (!sp.occlusion || !(distance > 0) || samples < 1) return 1.0f;
  if (!(length_squared(n) > 0)) n = sp.ns;
  const Frame frame(normalize(n));
  // A Hammersley set of `samples` points, shifted (Cranley-Patterson) by the position's hash.
  const Vec3 p = sp.p + Vec3(0.0f);  // -0 is 0
  const uint32_t h = hash3(std::bit_cast<uint32_t>(p.x), std::bit_cast<uint32_t>(p.y), std::bit_cast<uint32_t>(p.z));
  const float shift_u = u32_to_unit_float(h), shift_v = u32_to_unit_float(hash_u32(h ^ 0x68e31da4u));
  int unoccluded = 0;
  for (int i = 0; i < samples; ++i) {
    float u = (float(i) + 0.5f) / float(samples) + shift_u, v = u32_to_unit_float(reverse_bits(uint32_t(i))) + shift_v;
    u -= std::floor(u);
    v -= std::floor(v);
    const Vec3 d = frame.to_world(cosine_hemisphere(Vec2(std::min(u, 0.99999994f), std::min(v, 0.99999994f))));
    if (!sp.occlusion->texture_ray_occluded(sp, d, distance, only_local)) ++unoccluded;
  }
  return float(unoccluded) / float(samples);
}

}  // namespace rdv
