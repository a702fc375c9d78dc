// The hashes Blender's procedural textures draw their randomness from (Cycles 3.4's
// util/hash.h): Bob Jenkins' lookup3 of up to four 32-bit words, and the same of floats'
// bits mapped to [0, 1]. The same keys give the same values as Blender's, so a Voronoi
// cell or a White Noise pixel has Blender's colour, not just its statistics.
#pragma once
#include <cstdint>
#include <cstring>
#include "core/math.h"

namespace rdv::hash {

inline uint32_t rotate(uint32_t x, int k) { return (x << k) | (x >> (32 - k)); }

// lookup3's final mixing of (a, b, c), returning c.
inline uint32_t lookup3_final(uint32_t a, uint32_t b, uint32_t c) {
  c ^= b; c -= rotate(b, 14);
  a ^= c; a -= rotate(c, 11);
  b ^= a; b -= rotate(a, 25);
  c ^= b; c -= rotate(b, 16);
  a ^= c; a -= rotate(c, 4);
  b ^= a; b -= rotate(a, 14);
  c ^= b; c -= rotate(b, 24);
  return c;
}
// lookup3's mixing of (a, b, c), for keys of more than three words.
inline void lookup3_mix(uint32_t &a, uint32_t &b, uint32_t &c) {
  a -= c; a ^= rotate(c, 4); c += b;
  b -= a; b ^= rotate(a, 6); a += c;
  c -= b; c ^= rotate(b, 8); b += a;
  a -= c; a ^= rotate(c, 16); c += b;
  b -= a; b ^= rotate(a, 19); a += c;
  c -= b; c ^= rotate(b, 4); b += a;
}
// The seed is lookup3's, for a key of n words.
constexpr uint32_t seed(uint32_t words) { return 0xdeadbeefu + (words << 2) + 13u; }

inline uint32_t uint1(uint32_t x) { return lookup3_final(seed(1) + x, seed(1), seed(1)); }
inline uint32_t uint2(uint32_t x, uint32_t y) { return lookup3_final(seed(2) + x, seed(2) + y, seed(2)); }
inline uint32_t uint3(uint32_t x, uint32_t y, uint32_t z) {
  return lookup3_final(seed(3) + x, seed(3) + y, seed(3) + z);
}
inline uint32_t uint4(uint32_t x, uint32_t y, uint32_t z, uint32_t w) {
  uint32_t a = seed(4) + x, b = seed(4) + y, c = seed(4) + z;
  lookup3_mix(a, b, c);
  return lookup3_final(a + w, b, c);
}

inline uint32_t bits(float f) {
  uint32_t u;
  std::memcpy(&u, &f, 4);
  return u;
}
// [0, 2^32 - 1] -> [0, 1], both ends included (Cycles' uint_to_float_incl).
inline float unit(uint32_t h) { return float(h) * (1.0f / float(0xFFFFFFFFu)); }

// Floats' bits hashed to [0, 1].
inline float to_float(float x) { return unit(uint1(bits(x))); }
inline float to_float(float x, float y) { return unit(uint2(bits(x), bits(y))); }
inline float to_float(float x, float y, float z) { return unit(uint3(bits(x), bits(y), bits(z))); }
inline float to_float(float x, float y, float z, float w) {
  return unit(uint4(bits(x), bits(y), bits(z), bits(w)));
}

// One to four floats hashed to a colour (Cycles' hash_float{,2,3,4}_to_float3): the key
// extended by 1 and 2, or rotated for four.
inline Color float1_to_color(float x) { return {to_float(x), to_float(x, 1.0f), to_float(x, 2.0f)}; }
inline Color float2_to_color(float x, float y) {
  return {to_float(x, y), to_float(x, y, 1.0f), to_float(x, y, 2.0f)};
}
inline Color float3_to_color(float x, float y, float z) {
  return {to_float(x, y, z), to_float(x, y, z, 1.0f), to_float(x, y, z, 2.0f)};
}
inline Color float4_to_color(float x, float y, float z, float w) {
  return {to_float(x, y, z, w), to_float(z, x, w, y), to_float(w, z, y, x)};
}

}  // namespace rdv::hash
