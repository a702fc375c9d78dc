#include "textures/ambient_occlusion.h"
#include <cstring>
#include "core/hash.h"
#include "core/sampling.h"
#include "textures/shading_point.h"

namespace rdv {

namespace {

uint32_t float_bits(float x) {
  x += 0.0f;  // -0 is 0
  uint32_t u;
  std::memcpy(&u, &x, 4);
  return u;
}

float unit_float(uint32_t h) { return float(h >> 8) * (1.0f / 16777216.0f); }

// Van der Corput's radical inverse in base 2 (the second coordinate of a Hammersley set).
float radical_inverse2(uint32_t i) {
  i = (i << 16) | (i >> 16);
  i = ((i & 0x00ff00ffu) << 8) | ((i & 0xff00ff00u) >> 8);
  i = ((i & 0x0f0f0f0fu) << 4) | ((i & 0xf0f0f0f0u) >> 4);
  i = ((i & 0x33333333u) << 2) | ((i & 0xccccccccu) >> 2);
  i = ((i & 0x55555555u) << 1) | ((i & 0xaaaaaaaau) >> 1);
  return float(i >> 8) * (1.0f / 16777216.0f);
}

}  // namespace

float ambient_occlusion(const ShadingPoint &sp, Vec3 n, float distance, int samples, bool only_local) {
  if (!sp.occlusion || !(distance > 0) || samples < 1) return 1.0f;
  if (!(length_squared(n) > 0)) n = sp.ns;
  const Frame frame(normalize(n));
  // A Hammersley set of `samples` points, shifted (Cranley-Patterson) by the position's hash.
  const uint32_t h = hash3(float_bits(sp.p.x), float_bits(sp.p.y), float_bits(sp.p.z));
  const float shift_u = unit_float(h), shift_v = unit_float(hash_u32(h ^ 0x68e31da4u));
  int unoccluded = 0;
  for (int i = 0; i < samples; ++i) {
    float u = (float(i) + 0.5f) / float(samples) + shift_u, v = radical_inverse2(uint32_t(i)) + shift_v;
    u -= std::floor(u);
    v -= std::floor(v);
    const Vec3 d = frame.to_world(cosine_hemisphere(Vec2(std::min(u, 0.99999994f), std::min(v, 0.99999994f))));
    if (!sp.occlusion->texture_ray_occluded(sp, d, distance, only_local)) ++unoccluded;
  }
  return float(unoccluded) / float(samples);
}

}  // namespace rdv
