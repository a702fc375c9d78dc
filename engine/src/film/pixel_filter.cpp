#include "film/pixel_filter.h"
#include <algorithm>

namespace rdv {

PixelFilter::PixelFilter(float width) : width_(std::clamp(width, 1e-3f, kMaxWidth)), cdf_(kTableSize + 1) {
  // Piecewise-linear CDF from a fine table of the filter: inverted exactly below.
  double sum = 0;
  cdf_[0] = 0;
  const float support = 2.0f * width_;
  for (int i = 0; i < kTableSize; ++i) {
    float x = -width_ + (i + 0.5f) * support / kTableSize;
    sum += evaluate(x);
    cdf_[i + 1] = static_cast<float>(sum);
  }
  integral_ = static_cast<float>(sum * support / kTableSize);
  for (float &c : cdf_) c /= static_cast<float>(sum);
  // guide_[g]: the last table entry whose CDF is <= g / kGuideSize. kGuideSize is a power
  // of two, so u * kGuideSize and g / kGuideSize are exact and a u in cell g starts there.
  for (int g = 0, i = 0; g < kGuideSize; ++g) {
    const float lo = static_cast<float>(g) / kGuideSize;
    while (i < kTableSize && cdf_[i + 1] <= lo) ++i;
    guide_[g] = i;
  }
}

float PixelFilter::evaluate(float x) const {
  if (std::fabs(x) > width_) return 0;
  // cos(2t) and cos(3t) from c = cos(t) (Chebyshev): one cosine per tap, and every
  // Metropolis or light-tracing splat evaluates a few taps per axis.
  const float c = std::cos(2.0f * kPi * (x / (2.0f * width_) + 0.5f));
  return 0.35875f - 0.48829f * c + 0.14128f * (2.0f * c * c - 1.0f) - 0.01168f * c * (4.0f * c * c - 3.0f);
}

float PixelFilter::sample(float u) const {
  // The last entry with cdf_[i] <= u (what a binary search finds), from the guide table
  // and a short forward scan: two per camera sample, a binary search cost ~7% of a path
  // tracer's time on a Cornell box.
  int i = guide_[std::clamp(static_cast<int>(u * kGuideSize), 0, kGuideSize - 1)];
  while (i < kTableSize && cdf_[i + 1] <= u) ++i;
  i = std::min(i, kTableSize - 1);
  float width = cdf_[i + 1] - cdf_[i];
  float frac = width > 0 ? (u - cdf_[i]) / width : 0.5f;
  return -width_ + (i + frac) * 2.0f * width_ / kTableSize;
}

float PixelFilter::pdf(float x) const {
  if (std::fabs(x) >= width_) return 0;
  int i = std::clamp(static_cast<int>((x / (2.0f * width_) + 0.5f) * kTableSize), 0, kTableSize - 1);
  return (cdf_[i + 1] - cdf_[i]) * kTableSize / (2.0f * width_);
}

}  // namespace rdv
