#include "textures/pattern_textures.h"
#include <cmath>
#include "textures/hash.h"
#include "textures/noise.h"

namespace rdv {

float wave_texture(Vec3 p, const WaveParams &w) {
  p = (p + Vec3(0.000001f)) * 0.999999f;  // as Blender: no band edge exactly on a unit coordinate
  float n;
  if (w.type == WaveType::Bands) {
    switch (w.direction) {
      case 0: n = p.x * 20.0f; break;
      case 1: n = p.y * 20.0f; break;
      case 2: n = p.z * 20.0f; break;
      default: n = (p.x + p.y + p.z) * 10.0f; break;
    }
  } else {
    Vec3 r = p;
    if (w.direction == 0) r = r * Vec3(0, 1, 1);
    else if (w.direction == 1) r = r * Vec3(1, 0, 1);
    else if (w.direction == 2) r = r * Vec3(1, 1, 0);
    n = length(r) * 20.0f;
  }
  n += w.phase;
  if (w.distortion != 0.0f)
    n += w.distortion * (fractal_noise(p * w.detail_scale, w.detail, w.detail_roughness) * 2.0f - 1.0f);
  if (!std::isfinite(n)) return 0.0f;
  constexpr float k2Pi = 2.0f * kPi;
  switch (w.profile) {
    case WaveProfile::Sine: return 0.5f + 0.5f * std::sin(n - 0.5f * kPi);
    case WaveProfile::Saw: n /= k2Pi; return n - std::floor(n);
    default: n /= k2Pi; return std::fabs(n - std::floor(n + 0.5f)) * 2.0f;
  }
}

Color magic_texture(Vec3 p, float scale, int depth, float distortion) {
  // Each coordinate taken modulo 2 pi first, as Blender: large coordinates keep their detail.
  constexpr float k2Pi = 2.0f * kPi;
  const float px = std::fmod(p.x, k2Pi), py = std::fmod(p.y, k2Pi), pz = std::fmod(p.z, k2Pi);
  float x = std::sin((px + py + pz) * 5.0f * scale);
  float y = std::cos((-px + py - pz) * 5.0f * scale);
  float z = -std::cos((-px - py + pz) * 5.0f * scale);
  const float d = distortion;
  // The turns Blender nests: each replaces one coordinate by a sine or cosine of the three.
  if (depth > 0) {
    x *= d, y *= d, z *= d;
    y = -std::cos(x - y + z) * d;
    if (depth > 1) x = std::cos(x - y - z) * d;
    if (depth > 2) z = std::sin(-x - y - z) * d;
    if (depth > 3) x = -std::cos(-x + y - z) * d;
    if (depth > 4) y = -std::sin(-x + y + z) * d;
    if (depth > 5) y = -std::cos(-x + y + z) * d;
    if (depth > 6) x = std::cos(x + y + z) * d;
    if (depth > 7) z = std::sin(x + y - z) * d;
    if (depth > 8) x = -std::cos(-x - y + z) * d;
    if (depth > 9) y = -std::sin(x - y + z) * d;
  }
  if (d != 0.0f) x /= 2.0f * d, y /= 2.0f * d, z /= 2.0f * d;
  Color c(0.5f - x, 0.5f - y, 0.5f - z);
  return is_finite(c) ? c : Color(0.0f);
}

namespace {
// Blender's integer noise for a brick's tint, in [0, 1).
float brick_noise(uint32_t n) {
  n = (n + 1013) & 0x7fffffffu;
  n = (n >> 13) ^ n;
  const uint32_t nn = (n * (n * n * 60493u + 19990303u) + 1376312589u) & 0x7fffffffu;
  return 0.5f * (float(nn) / 1073741824.0f);
}
int floor_to_int(float x) {
  // Coordinates beyond int's range have no brick: clamp rather than overflow.
  const float f = std::floor(x);
  return f >= 2147483520.0f ? 2147483520 : f <= -2147483520.0f ? -2147483520 : std::isnan(f) ? 0 : int(f);
}
}  // namespace

BrickSample brick_texture(Vec3 p, const BrickParams &b) {
  float brick_width = b.brick_width, offset = 0;
  const int row = floor_to_int(p.y / b.row_height);
  if (b.offset_frequency && b.squash_frequency) {
    brick_width *= (row % b.squash_frequency) ? 1.0f : b.squash;
    offset = (row % b.offset_frequency) ? 0.0f : brick_width * b.offset;
  }
  const int brick = floor_to_int((p.x + offset) / brick_width);
  const float x = (p.x + offset) - brick_width * float(brick), y = p.y - b.row_height * float(row);
  const float tint = clampf(brick_noise((uint32_t(row) << 16) + (uint32_t(brick) & 0xFFFFu)) + b.bias, 0.0f, 1.0f);
  float min_dist = std::min(std::min(x, y), std::min(brick_width - x, b.row_height - y));
  float mortar;
  if (min_dist >= b.mortar_size) mortar = 0.0f;
  else if (b.mortar_smooth == 0.0f) mortar = 1.0f;
  else {
    min_dist = 1.0f - min_dist / b.mortar_size;
    const float t = min_dist / b.mortar_smooth, tt = t * t;
    mortar = min_dist < b.mortar_smooth ? 3.0f * tt - 2.0f * tt * t : 1.0f;
  }
  if (!std::isfinite(mortar)) mortar = 0.0f;
  return {std::isfinite(tint) ? tint : 0.0f, mortar};
}

Color white_noise_texture(Vec3 p, float w, int dims, bool color) {
  switch (dims) {
    case 1: return color ? hash::float1_to_color(w) : Color(hash::to_float(w));
    case 2: return color ? hash::float2_to_color(p.x, p.y) : Color(hash::to_float(p.x, p.y));
    case 4: return color ? hash::float4_to_color(p.x, p.y, p.z, w) : Color(hash::to_float(p.x, p.y, p.z, w));
    default: return color ? hash::float3_to_color(p.x, p.y, p.z) : Color(hash::to_float(p.x, p.y, p.z));
  }
}

}  // namespace rdv
