// Every random decision on a path draws from a Sampler, so integrators do not care
// where the numbers come from: a low-discrepancy sequence for path tracing, an
// independent stream, and (for MLT) a primary-sample-space sampler that replays and
// mutates them. The sequence of a sample depends on (seed, pixel, sample index)
// only: images are identical on any number of threads, and any sample can be replayed.
#pragma once
#include "core/hash.h"
#include "core/math.h"

namespace rdv {

// Separate streams of dimensions (pbrt-v3's MLTSampler idea). A sample starts on the
// Camera stream; every decision on a path draws at a position fixed by the path vertex
// it belongs to (samplers/dimension_layout.h), so a given decision (the light point for
// next-event estimation at the first hit, say) uses the same dimension in every sample
// of a pixel, whatever happened on the path before it (media, boundaries, transparent
// layers, subpath lengths). Stratification needs that, and so do MLT's
// primary-sample-space mutations: a small step stays a small change of the path.
enum class SampleStream : uint32_t {
  Camera = 0,          // the camera subpath (and the path tracer's path)
  Light = 1,           // the light subpath
  LightPoint = 2,      // next-event estimation (BDPT's s = 1) at each camera vertex
  Lens = 3,            // light tracing (BDPT's t = 1) from each light vertex
  CameraCrossing = 4,  // camera-path segments after a boundary or transparent layer
  LightCrossing = 5,   // light-path segments after a boundary
  Connection = 6,      // BDPT's inner connections (their transmittance)
  Strategy = 7         // multiplexed MLT: path depth (position 0), (s, t) strategy (position 1)
};
// Positions within a stream: [0, kMaxStreamPosition).
constexpr uint32_t kStreamShift = 25, kMaxStreamPosition = 1u << kStreamShift;

class Sampler {
 public:
  virtual ~Sampler() = default;
  virtual void start_sample(uint32_t px, uint32_t py, uint32_t sample_index) = 0;
  // Subsequent draws come from `stream`, starting at its dimension `position`.
  virtual void start_stream(SampleStream stream, uint32_t position) = 0;
  virtual float get_1d() = 0;
  virtual Vec2 get_2d() = 0;
};

// Owen-scrambled Sobol with per-dimension-pair padding (Burley 2020, "Practical
// Hash-based Owen Scrambling"): each pair of dimensions uses the first two Sobol
// dimensions of an index shuffled by a hash-seeded nested uniform scramble.
class SobolSampler final : public Sampler {
  // The second Sobol dimension (generator matrix: Pascal's triangle mod 2), bit-reversed,
  // a byte of the index at a time: the shuffled index uses all 32 bits, so a table
  // lookup per byte replaces a 32-step matrix-vector product.
  struct ReversedSobolTables {
    uint32_t t[4][256];
    ReversedSobolTables() {
      uint32_t v[32];
      v[0] = 1u << 31;
      for (int k = 1; k < 32; ++k) v[k] = v[k - 1] ^ (v[k - 1] >> 1);
      for (int b = 0; b < 4; ++b)
        for (int byte = 0; byte < 256; ++byte) {
          uint32_t r = 0;
          for (int j = 0; j < 8; ++j)
            if (byte & (1 << j)) r ^= v[8 * b + j];
          t[b][byte] = reverse_bits(r);
        }
    }
  };

 public:
  explicit SobolSampler(uint32_t seed) : seed_(hash_u32(seed ^ 0x5bd1e995u)) {}
  void start_sample(uint32_t px, uint32_t py, uint32_t sample_index) override {
    pixel_seed_ = hash3(px, py, seed_);
    reversed_index_ = reverse_bits(sample_index);
    dimension_ = 0;
  }
  // Dimensions only seed the per-dimension scramble (padding), so every dimension is
  // as good as any other: a stream is a disjoint block of them. The Camera stream is
  // block 0, the dimensions a sampler without streams would use. 2D draws hash their
  // dimension with another salt: a 1D and a 2D draw at one position are independent.
  void start_stream(SampleStream stream, uint32_t position) override {
    dimension_ = (uint32_t(stream) << kStreamShift) + (position & (kMaxStreamPosition - 1));
  }
  // Per dimension: shuffle the sample index with a nested uniform scramble, take the
  // first (and second) Sobol dimension of the shuffled index, and Owen-scramble those.
  // The Sobol dimension 0 point is the bit-reversed index and the scramble works on
  // reversed bits, so the reversals cancel in pairs and each coordinate costs one.
  float get_1d() override {
    uint32_t h = hash_combine(pixel_seed_, dimension_++);
    uint32_t i = reverse_bits(laine_karras(reversed_index_, h));
    return to_float(reverse_bits(laine_karras(i, hash_u32(h ^ 0x68bc21ebu))));
  }
  Vec2 get_2d() override {
    uint32_t h = hash_combine(pixel_seed_ ^ 0x2c1b3c6du, dimension_++);
    uint32_t i = reverse_bits(laine_karras(reversed_index_, h));
    uint32_t x = reverse_bits(laine_karras(i, hash_u32(h ^ 0x68bc21ebu)));
    uint32_t y = reverse_bits(laine_karras(reversed_sobol_dimension1(i), hash_u32(h ^ 0x02e5be93u)));
    return {to_float(x), to_float(y)};
  }

  static uint32_t reversed_sobol_dimension1(uint32_t index) {
    static const ReversedSobolTables tables;
    return tables.t[0][index & 0xff] ^ tables.t[1][(index >> 8) & 0xff] ^ tables.t[2][(index >> 16) & 0xff] ^
           tables.t[3][index >> 24];
  }
  // Laine-Karras style hash: on bit-reversed values it acts as a nested uniform (Owen)
  // scramble, each bit flipped depending only on the bits above it.
  static uint32_t laine_karras(uint32_t x, uint32_t seed) {
    x += seed;
    x ^= x * 0x6c50b47cu;
    x ^= x * 0xb82f1e52u;
    x ^= x * 0xc7afe638u;
    x ^= x * 0x8d22f6e6u;
    return x;
  }

 private:
  static float to_float(uint32_t v) { return u32_to_unit_float(v); }
  uint32_t seed_, pixel_seed_ = 0, reversed_index_ = 0, dimension_ = 0;
};

// Independent uniform numbers from a PCG stream seeded by (seed, pixel, index).
class IndependentSampler final : public Sampler {
 public:
  explicit IndependentSampler(uint32_t seed) : seed_(seed) {}
  void start_sample(uint32_t px, uint32_t py, uint32_t sample_index) override {
    sample_seed_ = hash3(px, py, seed_);
    sample_index_ = sample_index;
    rng_ = Pcg32(sample_seed_, (uint64_t(sample_index) << 1) | 1);
  }
  void start_stream(SampleStream stream, uint32_t position) override {
    rng_ = Pcg32(hash3(sample_seed_, uint32_t(stream), position), (uint64_t(sample_index_) << 1) | 1);
  }
  float get_1d() override { return rng_.next_float(); }
  Vec2 get_2d() override { float a = rng_.next_float(); return {a, rng_.next_float()}; }

 private:
  uint32_t seed_, sample_seed_ = 0, sample_index_ = 0;
  Pcg32 rng_;
};

}  // namespace rdv
