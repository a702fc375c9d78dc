// Piecewise-constant 1D distribution: light selection by power, and (later) the rows
// and columns of environment-map importance sampling.
#pragma once
#include <algorithm>
#include <vector>

namespace rdv {

class Distribution1D {
 public:
  Distribution1D() = default;
  explicit Distribution1D(const std::vector<float> &weights) : func_(weights), cdf_(weights.size() + 1) {
    cdf_[0] = 0;
    double sum = 0;
    for (size_t i = 0; i < func_.size(); ++i) {
      sum += std::max(0.0f, func_[i]);
      cdf_[i + 1] = static_cast<float>(sum);
    }
    total_ = static_cast<float>(sum);
    if (total_ > 0)
      for (float &c : cdf_) c /= total_;
  }
  size_t size() const { return func_.size(); }
  float total() const { return total_; }
  // Discrete sample: returns the index, its probability, and u remapped to [0,1).
  size_t sample_discrete(float u, float *pmf, float *u_remapped = nullptr) const {
    size_t i = std::upper_bound(cdf_.begin(), cdf_.end(), u) - cdf_.begin();
    i = std::clamp<size_t>(i == 0 ? 0 : i - 1, 0, func_.size() - 1);
    while (i + 1 < func_.size() && func_[i] <= 0) ++i;  // never return a zero-weight entry
    float width = cdf_[i + 1] - cdf_[i];
    if (pmf) *pmf = width;
    if (u_remapped) *u_remapped = width > 0 ? std::min((u - cdf_[i]) / width, 0.99999994f) : 0.0f;
    return i;
  }
  // Where entry i starts in [0, 1] (sample_discrete maps [cdf(i), cdf(i + 1)) to i).
  float cdf(size_t i) const { return cdf_[i]; }
  float pmf(size_t i) const { return total_ > 0 ? std::max(0.0f, func_[i]) / total_ : 0.0f; }

 private:
  std::vector<float> func_, cdf_;
  float total_ = 0;
};

}  // namespace rdv
