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
// lookup3's mixing of (a, b, c), for keys of more than three words (hash4).
void lookup3_mix(uint32_t &a, uint32_t &b, uint32_t &c) {
  a -= c; a ^= rotate(c, 4); c += b;
  b -= a; b ^= rotate(a, 6); a += c;
  c -= b; c ^= rotate(b, 8); b += a;
  a -= c; a ^= rotate(c, 16); c += b;
  b -= a; b ^= rotate(a, 19); a += c;
  c -= b; c ^= rotate(b, 4); b += a;
}
uint32_t hash1(uint32_t x) {
  const uint32_t seed = 0xdeadbeefu + (1u << 2) + 13u;
  return lookup3_final(seed + x, seed, seed);
}
uint32_t hash2(uint32_t x, uint32_t y) {
  const uint32_t seed = 0xdeadbeefu + (2u << 2) + 13u;
  return lookup3_final(seed + x, seed + y, seed);
}
uint32_t hash3(uint32_t x, uint32_t y, uint32_t z) {
  const uint32_t seed = 0xdeadbeefu + (3u << 2) + 13u;
  return lookup3_final(seed + x, seed + y, seed + z);
}
uint32_t hash4(uint32_t x, uint32_t y, uint32_t z, uint32_t w) {
  const uint32_t seed = 0xdeadbeefu + (4u << 2) + 13u;
  uint32_t a = seed + x, b = seed + y, c = seed + z;
  lookup3_mix(a, b, c);
  return lookup3_final(a + w, b, c);
}
uint32_t bits(float f) {
  uint32_t u;
  std::memcpy(&u, &f, 4);
  return u;
}

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
  i = int(f);
  return x - f;
}

float lerp(float a, float b, float t) { return a + t * (b - a); }

float perlin1(float x) {
  int X;
  const float fx = floor_frac(x, X);
  return lerp(gradient1(hash1(uint32_t(X)), fx), gradient1(hash1(uint32_t(X + 1)), fx - 1.0f), fade(fx));
}

float perlin2(float x, float y) {
  int X, Y;
  const float fx = floor_frac(x, X), fy = floor_frac(y, Y);
  const float u = fade(fx), v = fade(fy), x1 = 1.0f - u, y1 = 1.0f - v;
  auto corner = [&](int dx, int dy) {
    return gradient2(hash2(uint32_t(X + dx), uint32_t(Y + dy)), fx - float(dx), fy - float(dy));
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
      return gradient4(hash4(uint32_t(X + dx), uint32_t(Y + dy), uint32_t(Z + dz), uint32_t(W + dw)), fx - float(dx),
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
    return gradient(hash3(uint32_t(X + dx), uint32_t(Y + dy), uint32_t(Z + dz)), fx - float(dx), fy - float(dy),
                    fz - float(dz));
  };
  const float x1 = 1.0f - u, y1 = 1.0f - v, z1 = 1.0f - w;
  return z1 * (y1 * (corner(0, 0, 0) * x1 + corner(1, 0, 0) * u) + v * (corner(0, 1, 0) * x1 + corner(1, 1, 0) * u)) +
         w * (y1 * (corner(0, 0, 1) * x1 + corner(1, 0, 1) * u) + v * (corner(0, 1, 1) * x1 + corner(1, 1, 1) * u));
}

// A point of up to four coordinates (x, y, z and w), for the node's 1D, 2D, 3D and 4D noise.
struct Point {
  Vec3 p;
  float w;
  Point operator+(const Point &o) const { return {p + o.p, w + o.w}; }
  Point operator*(float k) const { return {p * k, w * k}; }
};

// Cycles' random_float{,2,3,4}_offset(seed): 100..200 along each axis the noise has, from the
// hash of the seed (and the axis), as floats' bits. 1D keeps its one coordinate in w.
Point offset(int dims, float seed) {
  auto unit = [](uint32_t h) { return float(h) * (1.0f / float(0xFFFFFFFFu)); };
  auto axis = [&](float a) { return 100.0f + unit(hash2(bits(seed), bits(a))) * 100.0f; };
  switch (dims) {
    case 1: return {Vec3(0.0f), 100.0f + unit(hash1(bits(seed))) * 100.0f};
    case 2: return {Vec3(axis(0.0f), axis(1.0f), 0.0f), 0.0f};
    case 4: return {Vec3(axis(0.0f), axis(1.0f), axis(2.0f)), axis(3.0f)};
    default: return {Vec3(axis(0.0f), axis(1.0f), axis(2.0f)), 0.0f};
  }
}

// Signed noise of each dimension, scaled to about [-1, 1] by Cycles' factors.
float signed_noise(int dims, const Point &q) {
  float n, k;
  switch (dims) {
    case 1: n = perlin1(q.w), k = 0.2500f; break;
    case 2: n = perlin2(q.p.x, q.p.y), k = 0.6616f; break;
    case 4: n = perlin4(q.p, q.w), k = 0.8344f; break;
    default: n = perlin(q.p), k = 0.9820f; break;
  }
  return k * (std::isfinite(n) ? n : 0.0f);
}

float fractal(int dims, const Point &q, float detail, float roughness) {
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
  Point of[6];
  explicit Offsets(int dims) {
    for (int i = 0; i < 6; ++i) of[i] = offset(dims, float(i));
  }
};

}  // namespace

float signed_noise(Vec3 p) { return signed_noise(3, Point{p, 0.0f}); }

float fractal_noise(Vec3 p, float detail, float roughness) { return fractal(3, Point{p, 0.0f}, detail, roughness); }

Color noise_texture(Vec3 p, float w, int dims, float detail, float roughness, float distortion, bool color) {
  static const Offsets offsets[4] = {Offsets(1), Offsets(2), Offsets(3), Offsets(4)};
  dims = dims >= 1 && dims <= 4 ? dims : 3;
  const Point *o = offsets[dims - 1].of;
  Point q{dims == 1 ? Vec3(0.0f) : dims == 2 ? Vec3(p.x, p.y, 0.0f) : p, dims == 1 || dims == 4 ? w : 0.0f};
  if (distortion != 0.0f) {  // each coordinate moved by the noise at an offset of its own
    Point d{Vec3(0.0f), 0.0f};
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
