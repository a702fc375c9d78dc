#include "samplers/pss_sampler.h"
#include <cmath>
#include "core/math.h"

namespace rdv {

float PssSampler::value(uint32_t dimension) {
  Value &v = values_[dimension];
  if (v.modified == iteration_) return v.value;  // read twice in one proposal
  // Not read since the last accepted large step: the value that step drew, lazily
  // (a large step draws afresh anyway).
  if (v.modified < last_large_step_ && !large_step_) {
    v.value = uniform();
    v.modified = last_large_step_;
  }
  v.backup = v.value;
  v.modified_backup = v.modified;
  changed_.push_back(&v);
  const bool depth_choice = dimension == kDepthChoice;
  if (large_step_) {
    v.value = uniform();
  } else if (!depth_choice) {
    // The small steps this value missed, at once: a wrapped normal of sqrt(k) widths.
    double k = double(iteration_ - v.modified);
    double u1 = 1.0 - double(rng_.next_u32()) * 0x1p-32, u2 = double(rng_.next_u32()) * 0x1p-32;
    double normal = std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * M_PI * u2);
    double x = double(v.value) + normal * step_size_ * std::sqrt(k);
    x -= std::floor(x);
    v.value = x < 1.0 ? float(x) : 0.0f;
    if (v.value >= 1.0f) v.value = 0x1.fffffep-1f;  // rounded up to 1 in float
  }
  v.modified = iteration_;
  return v.value;
}

}  // namespace rdv
