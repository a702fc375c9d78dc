// The primary-sample-space sampler of Metropolis light transport (Kelemen et al. 2002;
// pbrt-v3's MLTSampler): the state of a Markov chain is the vector of uniform numbers a
// path consumes, and the path code reads it through the ordinary Sampler interface.
// A proposal is a large step (every number drawn afresh) or a small step (every number
// moved by a wrapped normal of standard deviation step_size), both symmetric.
//
// Values are made lazily, as the path asks for them: each remembers the iteration it was
// last changed in, and a value asked for after k small steps it was not read in takes
// the k steps at once (the sum of k normals is a normal of sqrt(k) times the width).
// A value not read since the last accepted large step is drawn afresh.
//
// Streams: stream s at position p, component k (0, or 1 for the second value of a 2D
// draw) is dimension s + kSampleStreams * (2 p + k), so each stream has dimensions of its
// own and mutating the light subpath never moves a camera-subpath number.
// (Strategy, 0), multiplexed MLT's path depth, changes on large steps only.
#pragma once
#include <cstdint>
#include <vector>
#include "core/hash.h"
#include "samplers/sampler.h"

namespace rdv {

class PssSampler final : public Sampler {
 public:
  // rng_seed: the numbers of the first state (a bootstrap sample is replayed from its seed).
  // rng_seed, rng_stream: the numbers of the first state (a bootstrap sample is
  // replayed from them).
  PssSampler(uint64_t rng_seed, uint64_t rng_stream, float step_size, float large_step_probability)
      : rng_(rng_seed, rng_stream), step_size_(step_size), large_step_probability_(large_step_probability) {}

  // Mutations from here on draw from another generator (a chain's own, seeded by
  // (seed, chain)): two chains started from one bootstrap sample still differ.
  void reseed(uint64_t seed, uint64_t stream) { rng_ = Pcg32(seed, stream); }

  // Starts the next proposal: a large step with the set probability (the first
  // iteration of a new sampler is always one: its numbers are fresh).
  void start_iteration() {
    ++iteration_;
    large_step_ = iteration_ == 1 || rng_.next_float() < large_step_probability_;
  }
  void start_large_step() {  // the next proposal, forced to be a large step
    ++iteration_;
    large_step_ = true;
  }
  bool large_step() const { return large_step_; }
  // The proposal becomes the state.
  void accept() {
    if (large_step_) last_large_step_ = iteration_;
  }
  // The state stays: every number the proposal changed gets its old value back.
  void reject() {
    for (Value &v : values_)
      if (v.modified == iteration_) {
        v.value = v.backup;
        v.modified = v.modified_backup;
      }
    --iteration_;
  }

  void start_sample(uint32_t, uint32_t, uint32_t) override { start_stream(SampleStream::Camera, 0); }
  void start_stream(SampleStream stream, uint32_t position) override {
    stream_ = uint32_t(stream);
    position_ = position;
  }
  float get_1d() override { return value(dimension(position_++, 0)); }
  Vec2 get_2d() override {
    uint32_t p = position_++;
    float x = value(dimension(p, 0));
    return {x, value(dimension(p, 1))};
  }

  // Sets a number of the current proposal (multiplexed MLT's chain start puts its depth
  // choice where the bootstrap sample's depth lies).
  void set(SampleStream stream, uint32_t position, float value) {
    start_stream(stream, position);
    get_1d();
    values_[dimension(position, 0)].value = value;
  }

  // For tests: the number at a dimension as it stands (without touching it).
  size_t dimensions() const { return values_.size(); }
  float peek(size_t dimension) const { return dimension < values_.size() ? values_[dimension].value : -1.0f; }
  uint64_t iteration() const { return iteration_; }

 private:
  struct Value {
    float value = 0, backup = 0;
    int64_t modified = -1, modified_backup = -1;  // iteration of the last change (-1: never)
  };
  size_t dimension(uint32_t position, uint32_t component) const {
    return stream_ + size_t(kSampleStreams) * (2 * size_t(position) + component);
  }
  float value(size_t dimension);
  float uniform() { return rng_.next_float(); }

  Pcg32 rng_;
  float step_size_, large_step_probability_;
  std::vector<Value> values_;
  int64_t iteration_ = 0, last_large_step_ = 0;
  bool large_step_ = true;
  uint32_t stream_ = 0, position_ = 0;
};

}  // namespace rdv
