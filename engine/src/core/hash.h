// Integer hashes and a small PCG generator: the sources of every random number.
#pragma once
#include <cstdint>

namespace rdv {

inline uint32_t hash_u32(uint32_t x) {  // lowbias32 (Wellons)
  x ^= x >> 16; x *= 0x7feb352dU; x ^= x >> 15; x *= 0x846ca68bU; x ^= x >> 16;
  return x;
}
inline uint32_t hash_combine(uint32_t a, uint32_t b) { return hash_u32(a ^ (hash_u32(b) + 0x9e3779b9U + (a << 6) + (a >> 2))); }
inline uint32_t hash3(uint32_t a, uint32_t b, uint32_t c) { return hash_combine(hash_combine(a, b), c); }

// The bits of v in reverse order (van der Corput's radical inverse in base 2, as an integer).
inline uint32_t reverse_bits(uint32_t v) {
  v = ((v >> 1) & 0x55555555u) | ((v & 0x55555555u) << 1);
  v = ((v >> 2) & 0x33333333u) | ((v & 0x33333333u) << 2);
  v = ((v >> 4) & 0x0f0f0f0fu) | ((v & 0x0f0f0f0fu) << 4);
  v = ((v >> 8) & 0x00ff00ffu) | ((v & 0x00ff00ffu) << 8);
  return (v >> 16) | (v << 16);
}

inline float u32_to_unit_float(uint32_t v) {
  // 24 high bits, so the result is < 1 exactly.
  return static_cast<float>(v >> 8) * 0x1p-24f;
}

// PCG32 (O'Neill): for the independent sampler and tests.
class Pcg32 {
 public:
  explicit Pcg32(uint64_t seed = 0x853c49e6748fea9bULL, uint64_t stream = 0xda3e39cb94b95bdbULL) {
    state_ = 0; inc_ = (stream << 1u) | 1u; next_u32(); state_ += seed; next_u32();
  }
  uint32_t next_u32() {
    uint64_t old = state_;
    state_ = old * 6364136223846793005ULL + inc_;
    uint32_t xorshifted = static_cast<uint32_t>(((old >> 18u) ^ old) >> 27u);
    uint32_t rot = static_cast<uint32_t>(old >> 59u);
    return (xorshifted >> rot) | (xorshifted << ((~rot + 1u) & 31));
  }
  float next_float() { return u32_to_unit_float(next_u32()); }
 private:
  uint64_t state_, inc_;
};

}  // namespace rdv
