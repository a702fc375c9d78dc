#include "textures/noise.h"
#include <cmath>
#include <cstdint>
#include "textures/hash.h"

namespace rdv {

namespace {

using hash::uint1;
using hash::uint2;
using hash::uint3;
using hash::uint4;

float fade(float t) { return t * t * t * (t * (t * 6.0f - 15.0f) + 10.0f); }

float negate_if(float v, uint32_t condition) { return condition ? -v : v; }

// The lattice gradients of each dimension, dotted with the corner's offset: 1D slopes 1..8,
// 2D's 8 directions, 3D improved Perlin noise's 12 edges (4 repeated), 4D's 32 edges.
float gradient1(uint32_t hash, float x) {
  const uint32_t h = hash & 15u;
  return negate_if(float(1 + (h & 7u)), h & 8u) * x;
}
float gradient2(uint32_t hash, float x, float y) {
  const uint32_t h = hash & 7u;
  const float u = h < 4 ? x : y, v = 2.0f * (h < 4 ? y : x);
  return negate_if(u, h & 1u) + negate_if(v, h & 2u);
}
float gradient4(uint32_t hash, float x, float y, float z, float w) {
  const uint32_t h = hash & 31u;
  const float u = h < 24 ? x : y, v = h < 16 ? y : z, s = h < 8 ? z : w;
  return negate_if(u, h & 1u) + negate_if(v, h & 2u) + negate_if(s, h & 4u);
}
float gradient(uint32_t hash, float x, float y, float z) {
  const int h = int(hash & 15u);
  const float u = h < 8 ? x : y;
  const float v = h < 4 ? y : (h == 12 || h == 14) ? x : z;
  return ((h & 1) ? -u : u) + ((h & 2) ? -v : v);
}

float floor_frac(float x, int &i) {
  const float f = std::floor(x);
  // Lattice indices are ints: beyond their range (a huge scale or coordinate, or NaN) the cell
  // is 0, a defined value where the conversion would be undefined (found by fuzz_abi_calls).
  i = std::fabs(f) < 2147483520.0f ? int(f) : 0;
  return x - f;
}

float lerp(float a, float b, float t) { return a + t * (b - a); }

float perlin1(float x) {
  int X;
  const float fx = floor_frac(x, X);
  return lerp(gradient1(uint1(uint32_t(X)), fx), gradient1(uint1(uint32_t(X + 1)), fx - 1.0f), fade(fx));
}

float perlin2(float x, float y) {
  int X, Y;
  const float fx = floor_frac(x, X), fy = floor_frac(y, Y);
  const float u = fade(fx), v = fade(fy), x1 = 1.0f - u, y1 = 1.0f - v;
  auto corner = [&](int dx, int dy) {
    return gradient2(uint2(uint32_t(X + dx), uint32_t(Y + dy)), fx - float(dx), fy - float(dy));
  };
  return y1 * (corner(0, 0) * x1 + corner(1, 0) * u) + v * (corner(0, 1) * x1 + corner(1, 1) * u);
}

float perlin4(Vec3 p, float w4) {
  int X, Y, Z, W;
  const float fx = floor_frac(p.x, X), fy = floor_frac(p.y, Y), fz = floor_frac(p.z, Z), fw = floor_frac(w4, W);
  const float u = fade(fx), v = fade(fy), t = fade(fz), s = fade(fw);
  const float x1 = 1.0f - u, y1 = 1.0f - v, z1 = 1.0f - t;
  auto cube = [&](int dw) {
    auto corner = [&](int dx, int dy, int dz) {
      return gradient4(uint4(uint32_t(X + dx), uint32_t(Y + dy), uint32_t(Z + dz), uint32_t(W + dw)), fx - float(dx),
                       fy - float(dy), fz - float(dz), fw - float(dw));
    };
    return z1 * (y1 * (corner(0, 0, 0) * x1 + corner(1, 0, 0) * u) + v * (corner(0, 1, 0) * x1 + corner(1, 1, 0) * u)) +
           t * (y1 * (corner(0, 0, 1) * x1 + corner(1, 0, 1) * u) + v * (corner(0, 1, 1) * x1 + corner(1, 1, 1) * u));
  };
  return lerp(cube(0), cube(1), s);
}

float perlin(Vec3 p) {
  int X, Y, Z;
  const float fx = floor_frac(p.x, X), fy = floor_frac(p.y, Y), fz = floor_frac(p.z, Z);
  const float u = fade(fx), v = fade(fy), w = fade(fz);
  auto corner = [&](int dx, int dy, int dz) {
    return gradient(uint3(uint32_t(X + dx), uint32_t(Y + dy), uint32_t(Z + dz)), fx - float(dx), fy - float(dy),
                    fz - float(dz));
  };
  const float x1 = 1.0f - u, y1 = 1.0f - v, z1 = 1.0f - w;
  return z1 * (y1 * (corner(0, 0, 0) * x1 + corner(1, 0, 0) * u) + v * (corner(0, 1, 0) * x1 + corner(1, 1, 0) * u)) +
         w * (y1 * (corner(0, 0, 1) * x1 + corner(1, 0, 1) * u) + v * (corner(0, 1, 1) * x1 + corner(1, 1, 1) * u));
}

// Cycles' random_float{,2,3,4}_offset(seed): 100..200 along each axis the noise has, from the
// hash of the seed (and the axis), as floats' bits. 1D keeps its one coordinate in w.
NoisePoint offset(int dims, float seed) {
  auto axis = [&](float a) { return 100.0f + hash::to_float(seed, a) * 100.0f; };
  switch (dims) {
    case 1: return {Vec3(0.0f), 100.0f + hash::to_float(seed) * 100.0f};
    case 2: return {Vec3(axis(0.0f), axis(1.0f), 0.0f), 0.0f};
    case 4: return {Vec3(axis(0.0f), axis(1.0f), axis(2.0f)), axis(3.0f)};
    default: return {Vec3(axis(0.0f), axis(1.0f), axis(2.0f)), 0.0f};
  }
}

}  // namespace

float signed_noise(int dims, const NoisePoint &q) {
  float n, k;
  switch (dims) {
    case 1: n = perlin1(q.w), k = 0.2500f; break;
    case 2: n = perlin2(q.p.x, q.p.y), k = 0.6616f; break;
    case 4: n = perlin4(q.p, q.w), k = 0.8344f; break;
    default: n = perlin(q.p), k = 0.9820f; break;
  }
  return k * (std::isfinite(n) ? n : 0.0f);
}

namespace {

float fractal(int dims, const NoisePoint &q, float detail, float roughness) {
  float fscale = 1.0f, amp = 1.0f, maxamp = 0.0f, sum = 0.0f;
  const float octaves = clampf(detail, 0.0f, 15.0f), gain = clampf(roughness, 0.0f, 1.0f);
  const int n = int(octaves);
  for (int i = 0; i <= n; ++i) {
    sum += (0.5f * signed_noise(dims, q * fscale) + 0.5f) * amp;
    maxamp += amp;
    amp *= gain;
    fscale *= 2.0f;
  }
  const float rmd = octaves - std::floor(octaves);
  if (rmd == 0.0f) return sum / maxamp;
  const float t = 0.5f * signed_noise(dims, q * fscale) + 0.5f;
  return (1.0f - rmd) * (sum / maxamp) + rmd * ((sum + t * amp) / (maxamp + amp));
}

// The offsets a node of each dimension uses (distortion's, then the Color output's two).
struct Offsets {
  NoisePoint of[6];
  explicit Offsets(int dims) {
    for (int i = 0; i < 6; ++i) of[i] = offset(dims, float(i));
  }
};

}  // namespace

float signed_noise(Vec3 p) { return signed_noise(3, NoisePoint{p, 0.0f}); }

float fractal_noise(Vec3 p, float detail, float roughness) { return fractal(3, NoisePoint{p, 0.0f}, detail, roughness); }

Color noise_texture(Vec3 p, float w, int dims, float detail, float roughness, float distortion, bool color) {
  static const Offsets offsets[4] = {Offsets(1), Offsets(2), Offsets(3), Offsets(4)};
  dims = dims >= 1 && dims <= 4 ? dims : 3;
  const NoisePoint *o = offsets[dims - 1].of;
  NoisePoint q = noise_point(p, w, dims);
  if (distortion != 0.0f) {  // each coordinate moved by the noise at an offset of its own
    NoisePoint d{Vec3(0.0f), 0.0f};
    if (dims == 1) d.w = signed_noise(1, q + o[0]);
    if (dims >= 2) d.p = Vec3(signed_noise(dims, q + o[0]), signed_noise(dims, q + o[1]), 0.0f);
    if (dims >= 3) d.p.z = signed_noise(dims, q + o[2]);
    if (dims == 4) d.w = signed_noise(dims, q + o[3]);
    q = q + d * distortion;
  }
  const float value = fractal(dims, q, detail, roughness);
  if (!color) return Color(value);
  const int c = dims == 1 ? 1 : dims;  // the Color output's offsets follow distortion's
  return {value, fractal(dims, q + o[c], detail, roughness), fractal(dims, q + o[c + 1], detail, roughness)};
}

}  // namespace rdv
