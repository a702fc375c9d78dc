// A run of random numbers for an estimator that needs an unbounded number of them
// (delta and ratio tracking, ray marching, emission gathering, the transmittance of a
// shadow ray): the first `count` come from the sampler at consecutive fixed positions
// of one stream (samplers/dimension_layout.h); any further ones from a PCG generator
// seeded by a hash of those `count` values.
//
// Why that keeps a small step in primary-sample space small (MLT): almost every
// estimate (about 99% of tracking segments in the smoke and fire scenes, all of a
// homogeneous medium's) uses no more than `count` numbers, so it is a function of
// sampler dimensions only and moves a little when they move a little. Only the rare
// long run continues with numbers that change completely with any change of its first
// `count`: there the proposal is a fresh estimate of the same quantity, still
// unbiased, and replaying the same primary samples still replays it exactly.
#pragma once
#include <bit>
#include <optional>
#include "core/hash.h"
#include "samplers/sampler.h"

namespace rdv {

class SampleRun {
 public:
  SampleRun(Sampler &sampler, SampleStream stream, uint32_t position, uint32_t count)
      : sampler_(&sampler), stream_(stream), position_(position), count_(count) {}
  // Numbers from `generator` only: for estimates outside a path (tests drive media so).
  explicit SampleRun(Pcg32 generator) : sampler_(nullptr), count_(0), drawn_(1), rng_(generator) {}
  float next_float() {
    if (drawn_ < count_) {
      sampler_->start_stream(stream_, position_ + drawn_++);
      float u = sampler_->get_1d();
      mix(u);
      return u;
    }
    return generator().next_float();
  }
  uint32_t drawn() const { return drawn_; }

 private:
  void mix(float u) { seed_ = hash_combine(seed_, std::bit_cast<uint32_t>(u)); }
  Pcg32 &generator() {
    if (drawn_++ == count_) rng_.emplace((uint64_t(seed_) << 32) | hash_u32(seed_ ^ position_), uint32_t(stream_));
    return *rng_;
  }
  Sampler *sampler_;
  SampleStream stream_ = SampleStream::Camera;
  uint32_t position_ = 0, count_, drawn_ = 0;
  uint32_t seed_ = 0x6a09e667u;
  std::optional<Pcg32> rng_;  // made only when the run outgrows its fixed dimensions
};

}  // namespace rdv
