#include "textures/noise.h"
#include <cmath>
#include <cstdint>
#include <cstring>

namespace rdv {

namespace {

uint32_t rotate(uint32_t x, int k) { return (x << k) | (x >> (32 - k)); }

// lookup3's final mixing of (a, b, c), returning c: the hash Cycles picks gradients and
// offsets with (its hash_uint2 / hash_uint3, seeded by the key length).
uint32_t lookup3_final(uint32_t a, uint32_t b, uint32_t c) {
  c ^= b; c -= rotate(b, 14);
  a ^= c; a -= rotate(c, 11);
  b ^= a; b -= rotate(a, 25);
  c ^= b; c -= rotate(b, 16);
  a ^= c; a -= rotate(c, 4);
  b ^= a; b -= rotate(a, 14);
  c ^= b; c -= rotate(b, 24);
  return c;
}
uint32_t hash2(uint32_t x, uint32_t y) {
  const uint32_t seed = 0xdeadbeefu + (2u << 2) + 13u;
  return lookup3_final(seed + x, seed + y, seed);
}
uint32_t hash3(uint32_t x, uint32_t y, uint32_t z) {
  const uint32_t seed = 0xdeadbeefu + (3u << 2) + 13u;
  return lookup3_final(seed + x, seed + y, seed + z);
}
uint32_t bits(float f) {
  uint32_t u;
  std::memcpy(&u, &f, 4);
  return u;
}

float fade(float t) { return t * t * t * (t * (t * 6.0f - 15.0f) + 10.0f); }

// Improved Perlin noise's 12 edge gradients (with 4 repeated) dotted with the corner offset.
float gradient(uint32_t hash, float x, float y, float z) {
  const int h = int(hash & 15u);
  const float u = h < 8 ? x : y;
  const float v = h < 4 ? y : (h == 12 || h == 14) ? x : z;
  return ((h & 1) ? -u : u) + ((h & 2) ? -v : v);
}

float floor_frac(float x, int &i) {
  const float f = std::floor(x);
  i = int(f);
  return x - f;
}

float perlin(Vec3 p) {
  int X, Y, Z;
  const float fx = floor_frac(p.x, X), fy = floor_frac(p.y, Y), fz = floor_frac(p.z, Z);
  const float u = fade(fx), v = fade(fy), w = fade(fz);
  auto corner = [&](int dx, int dy, int dz) {
    return gradient(hash3(uint32_t(X + dx), uint32_t(Y + dy), uint32_t(Z + dz)), fx - float(dx), fy - float(dy),
                    fz - float(dz));
  };
  const float x1 = 1.0f - u, y1 = 1.0f - v, z1 = 1.0f - w;
  return z1 * (y1 * (corner(0, 0, 0) * x1 + corner(1, 0, 0) * u) + v * (corner(0, 1, 0) * x1 + corner(1, 1, 0) * u)) +
         w * (y1 * (corner(0, 0, 1) * x1 + corner(1, 0, 1) * u) + v * (corner(0, 1, 1) * x1 + corner(1, 1, 1) * u));
}

// Cycles' random_float3_offset(seed): a point 100..200 away on each axis, from the hash of
// the seed and the axis (as floats' bits).
Vec3 offset(float seed) {
  auto axis = [seed](float a) { return 100.0f + float(hash2(bits(seed), bits(a))) * (1.0f / float(0xFFFFFFFFu)) * 100.0f; };
  return {axis(0.0f), axis(1.0f), axis(2.0f)};
}

}  // namespace

float signed_noise(Vec3 p) {
  const float n = perlin(p);
  return 0.9820f * (std::isfinite(n) ? n : 0.0f);
}

float fractal_noise(Vec3 p, float detail, float roughness) {
  float fscale = 1.0f, amp = 1.0f, maxamp = 0.0f, sum = 0.0f;
  const float octaves = clampf(detail, 0.0f, 15.0f), gain = clampf(roughness, 0.0f, 1.0f);
  const int n = int(octaves);
  for (int i = 0; i <= n; ++i) {
    sum += (0.5f * signed_noise(p * fscale) + 0.5f) * amp;
    maxamp += amp;
    amp *= gain;
    fscale *= 2.0f;
  }
  const float rmd = octaves - std::floor(octaves);
  if (rmd == 0.0f) return sum / maxamp;
  const float t = 0.5f * signed_noise(p * fscale) + 0.5f;
  return (1.0f - rmd) * (sum / maxamp) + rmd * ((sum + t * amp) / (maxamp + amp));
}

Color noise_texture(Vec3 p, float detail, float roughness, float distortion, bool color) {
  if (distortion != 0.0f) {
    static const Vec3 o0 = offset(0.0f), o1 = offset(1.0f), o2 = offset(2.0f);
    p = p + Vec3(signed_noise(p + o0), signed_noise(p + o1), signed_noise(p + o2)) * distortion;
  }
  const float value = fractal_noise(p, detail, roughness);
  if (!color) return Color(value);
  static const Vec3 o3 = offset(3.0f), o4 = offset(4.0f);
  return {value, fractal_noise(p + o3, detail, roughness), fractal_noise(p + o4, detail, roughness)};
}

}  // namespace rdv
