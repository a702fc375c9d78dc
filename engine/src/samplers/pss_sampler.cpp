#include "samplers/pss_sampler.h"
#include <cmath>
#include "core/math.h"

namespace rdv {

void PssSampler::grow() {
  std::vector<uint32_t> keys = std::move(keys_), indices = std::move(indices_);
  ++table_bits_;
  keys_.assign(size_t(1) << table_bits_, 0);
  indices_.assign(keys_.size(), 0);
  const uint32_t mask = uint32_t(keys_.size()) - 1;
  for (size_t i = 0; i < keys.size(); ++i) {
    if (keys[i] == 0) continue;
    uint32_t h = slot(keys[i]);
    while (keys_[h] != 0) h = (h + 1) & mask;
    keys_[h] = keys[i];
    indices_[h] = indices[i];
  }
}

float PssSampler::normal() {
  // Box-Muller makes two independent normals: the second serves the next call. In
  // float: a step is ~1% of the unit interval, and libm's float log and sincos cost
  // half the double ones (in double they were 4.5% of pssmlt's time on the door gap).
  if (has_spare_normal_) {
    has_spare_normal_ = false;
    return spare_normal_;
  }
  const float u1 = 1.0f - rng_.next_float(), u2 = rng_.next_float();  // u1 in (0, 1]
  const float r = std::sqrt(-2.0f * std::log(u1));
  float sin_phi, cos_phi;
  sincosf(2.0f * kPi * u2, &sin_phi, &cos_phi);
  spare_normal_ = r * sin_phi;
  has_spare_normal_ = true;
  return r * cos_phi;
}

float PssSampler::value(uint32_t dimension) {
  const uint32_t index = find(dimension);
  Value &v = values_[index];
  if (v.modified == iteration_) return v.value;  // read twice in one proposal
  // Not read since the last accepted large step: the value that step drew, lazily
  // (a large step draws afresh anyway).
  if (v.modified < last_large_step_ && !large_step_) {
    v.value = uniform();
    v.modified = last_large_step_;
  }
  v.backup = v.value;
  v.modified_backup = v.modified;
  changed_.push_back(index);
  const bool depth_choice = dimension == kDepthChoice;
  if (large_step_) {
    v.value = uniform();
  } else if (!depth_choice) {
    // The small steps this value missed, at once: a wrapped normal of sqrt(k) widths.
    double k = double(iteration_ - v.modified);
    double x = double(v.value) + normal() * step_size_ * (k == 1 ? 1.0 : std::sqrt(k));
    x -= std::floor(x);
    v.value = x < 1.0 ? float(x) : 0.0f;
    if (v.value >= 1.0f) v.value = 0x1.fffffep-1f;  // rounded up to 1 in float
  }
  v.modified = iteration_;
  return v.value;
}

}  // namespace rdv
