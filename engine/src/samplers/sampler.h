// Every random decision on a path draws from a Sampler, so integrators do not care
// where the numbers come from: a low-discrepancy sequence for path tracing, an
// independent stream, and (for MLT) a primary-sample-space sampler that replays and
// mutates them. The sequence of a sample depends on (seed, pixel, sample index)
// only: images are identical on any number of threads, and any sample can be replayed.
#pragma once
#include "core/hash.h"
#include "core/math.h"

namespace rdv {

class Sampler {
 public:
  virtual ~Sampler() = default;
  virtual void start_sample(uint32_t px, uint32_t py, uint32_t sample_index) = 0;
  virtual float get_1d() = 0;
  virtual Vec2 get_2d() = 0;
};

// Owen-scrambled Sobol with per-dimension-pair padding (Burley 2020, "Practical
// Hash-based Owen Scrambling"): each pair of dimensions uses the first two Sobol
// dimensions of an index shuffled by a hash-seeded nested uniform scramble.
class SobolSampler final : public Sampler {
  struct SobolTables {
    uint32_t t[4][256];
    SobolTables() {
      uint32_t v[32];
      v[0] = 1u << 31;
      for (int k = 1; k < 32; ++k) v[k] = v[k - 1] ^ (v[k - 1] >> 1);
      for (int b = 0; b < 4; ++b)
        for (int byte = 0; byte < 256; ++byte) {
          uint32_t r = 0;
          for (int j = 0; j < 8; ++j)
            if (byte & (1 << j)) r ^= v[8 * b + j];
          t[b][byte] = r;
        }
    }
  };

 public:
  explicit SobolSampler(uint32_t seed) : seed_(hash_u32(seed ^ 0x5bd1e995u)) {}
  void start_sample(uint32_t px, uint32_t py, uint32_t sample_index) override {
    pixel_seed_ = hash3(px, py, seed_);
    index_ = sample_index;
    dimension_ = 0;
  }
  float get_1d() override {
    uint32_t d = dimension_++;
    uint32_t h = hash_combine(pixel_seed_, d);
    uint32_t i = nested_uniform_scramble(index_, h);
    return to_float(nested_uniform_scramble(reverse_bits(i), hash_u32(h ^ 0x68bc21ebu)));
  }
  Vec2 get_2d() override {
    uint32_t d = dimension_++;
    uint32_t h = hash_combine(pixel_seed_, d + 0x10000);
    uint32_t i = nested_uniform_scramble(index_, h);
    uint32_t x = nested_uniform_scramble(reverse_bits(i), hash_u32(h ^ 0x68bc21ebu));
    uint32_t y = nested_uniform_scramble(sobol_dimension1(i), hash_u32(h ^ 0x02e5be93u));
    return {to_float(x), to_float(y)};
  }

  static uint32_t reverse_bits(uint32_t v) {
    v = ((v >> 1) & 0x55555555u) | ((v & 0x55555555u) << 1);
    v = ((v >> 2) & 0x33333333u) | ((v & 0x33333333u) << 2);
    v = ((v >> 4) & 0x0f0f0f0fu) | ((v & 0x0f0f0f0fu) << 4);
    v = ((v >> 8) & 0x00ff00ffu) | ((v & 0x00ff00ffu) << 8);
    return (v >> 16) | (v << 16);
  }
  // Second Sobol dimension (generator matrix: Pascal's triangle mod 2). The shuffled
  // index uses all 32 bits, so the matrix-vector product goes a byte at a time
  // through precomputed tables instead of a 32-step loop.
  static uint32_t sobol_dimension1(uint32_t index) {
    static const SobolTables tables;
    return tables.t[0][index & 0xff] ^ tables.t[1][(index >> 8) & 0xff] ^ tables.t[2][(index >> 16) & 0xff] ^
           tables.t[3][index >> 24];
  }
  // Laine-Karras style hash acting as a nested uniform (Owen) scramble on reversed bits.
  static uint32_t nested_uniform_scramble(uint32_t x, uint32_t seed) {
    x = reverse_bits(x);
    x += seed;
    x ^= x * 0x6c50b47cu;
    x ^= x * 0xb82f1e52u;
    x ^= x * 0xc7afe638u;
    x ^= x * 0x8d22f6e6u;
    return reverse_bits(x);
  }

 private:
  static float to_float(uint32_t v) { return u32_to_unit_float(v); }
  uint32_t seed_, pixel_seed_ = 0, index_ = 0, dimension_ = 0;
};

// Independent uniform numbers from a PCG stream seeded by (seed, pixel, index).
class IndependentSampler final : public Sampler {
 public:
  explicit IndependentSampler(uint32_t seed) : seed_(seed) {}
  void start_sample(uint32_t px, uint32_t py, uint32_t sample_index) override {
    rng_ = Pcg32(hash3(px, py, seed_), (uint64_t(sample_index) << 1) | 1);
  }
  float get_1d() override { return rng_.next_float(); }
  Vec2 get_2d() override { float a = rng_.next_float(); return {a, rng_.next_float()}; }

 private:
  uint32_t seed_;
  Pcg32 rng_;
};

}  // namespace rdv
