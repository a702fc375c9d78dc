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
// draw) is a dimension of its own, so mutating the light subpath never moves a
// camera-subpath number. Positions are sparse (samplers/dimension_layout.h gives each
// path vertex a fixed block), so the numbers live in a hash table by dimension: open
// addressing in flat arrays (a BDPT sample reads a hundred or more numbers; a node-based
// map's lookups cost MLT about a third of its mutations per second).
// (Strategy, 0), multiplexed MLT's path depth, changes on large steps only.
#pragma once
#include <cstdint>
#include <vector>
#include "core/hash.h"
#include "samplers/sampler.h"

namespace rdv {

class PssSampler final : public Sampler {
 public:
  // rng_seed, rng_stream: the numbers of the first state (a bootstrap sample is
  // replayed from them).
  PssSampler(uint64_t rng_seed, uint64_t rng_stream, float step_size, float large_step_probability)
      : rng_(rng_seed, rng_stream), step_size_(step_size), large_step_probability_(large_step_probability) {}

  // Mutations from here on draw from another generator (a chain's own, seeded by
  // (seed, chain)): two chains started from one bootstrap sample still differ.
  void reseed(uint64_t seed, uint64_t stream) {
    rng_ = Pcg32(seed, stream);
    has_spare_normal_ = false;
  }

  // Starts the next proposal: a large step with the set probability (the first
  // iteration of a new sampler is always one: its numbers are fresh).
  void start_iteration() {
    changed_.clear();
    ++iteration_;
    large_step_ = iteration_ == 1 || rng_.next_float() < large_step_probability_;
  }
  bool large_step() const { return large_step_; }
  // The proposal becomes the state.
  void accept() {
    if (large_step_) last_large_step_ = iteration_;
    changed_.clear();
  }
  // The state stays: every number the proposal changed gets its old value back.
  void reject() {
    for (uint32_t i : changed_) {
      Value &v = values_[i];
      v.value = v.backup;
      v.modified = v.modified_backup;
    }
    changed_.clear();
    --iteration_;
  }

  void start_sample(uint32_t, uint32_t, uint32_t) override { start_stream(SampleStream::Camera, 0); }
  void start_stream(SampleStream stream, uint32_t position) override {
    stream_ = uint32_t(stream);
    position_ = position;
  }
  float get_1d() override { return value(dimension(stream_, position_++, 0)); }
  Vec2 get_2d() override {
    uint32_t p = position_++;
    float x = value(dimension(stream_, p, 0));
    return {x, value(dimension(stream_, p, 1))};
  }

  // Sets a number of the current proposal (multiplexed MLT's chain start puts its depth
  // choice where the bootstrap sample's depth lies).
  void set(SampleStream stream, uint32_t position, float value) {
    start_stream(stream, position);
    get_1d();
    values_[find(dimension(uint32_t(stream), position, 0))].value = value;
  }

  // For tests: how many numbers exist, and one as it stands (-1: never drawn).
  size_t dimensions() const { return values_.size(); }
  float peek(SampleStream stream, uint32_t position, uint32_t component) const {
    const uint32_t key = dimension(uint32_t(stream), position, component) + 1;
    for (uint32_t h = slot(key);; h = (h + 1) & (uint32_t(keys_.size()) - 1)) {
      if (keys_[h] == 0) return -1.0f;
      if (keys_[h] == key) return values_[indices_[h]].modified < 0 ? -1.0f : values_[indices_[h]].value;
    }
  }
  uint64_t iteration() const { return iteration_; }

 private:
  struct Value {
    float value = 0, backup = 0;
    int64_t modified = -1, modified_backup = -1;  // iteration of the last change (-1: never)
  };
  // Positions are below kMaxStreamPosition = 2^25 and streams below 8: 29 bits.
  static uint32_t dimension(uint32_t stream, uint32_t position, uint32_t component) {
    return (stream << (kStreamShift + 1)) | (2 * position + component);
  }
  static constexpr uint32_t kDepthChoice = uint32_t(SampleStream::Strategy) << (kStreamShift + 1);
  float value(uint32_t dimension);
  float uniform() { return rng_.next_float(); }
  float normal();
  // The table: keys_ holds dimension + 1 (0: empty slot), indices_ the value's index.
  uint32_t slot(uint32_t key) const { return (key * 0x9e3779b1u) >> (32 - table_bits_); }
  // Index of the dimension's value in values_, created (never drawn) if new.
  uint32_t find(uint32_t dimension) {
    const uint32_t key = dimension + 1, mask = uint32_t(keys_.size()) - 1;
    for (uint32_t h = slot(key);; h = (h + 1) & mask) {
      if (keys_[h] == key) return indices_[h];
      if (keys_[h] == 0) {
        keys_[h] = key;
        indices_[h] = uint32_t(values_.size());
        values_.emplace_back();
        if (2 * values_.size() > keys_.size()) grow();
        return uint32_t(values_.size() - 1);
      }
    }
  }
  void grow();

  Pcg32 rng_;
  float step_size_, large_step_probability_;
  std::vector<Value> values_;
  uint32_t table_bits_ = 8;
  std::vector<uint32_t> keys_ = std::vector<uint32_t>(256, 0), indices_ = std::vector<uint32_t>(256, 0);
  std::vector<uint32_t> changed_;  // values the current proposal changed
  float spare_normal_ = 0;
  bool has_spare_normal_ = false;
  int64_t iteration_ = 0, last_large_step_ = 0;
  bool large_step_ = true;
  uint32_t stream_ = 0, position_ = 0;
};

}  // namespace rdv
