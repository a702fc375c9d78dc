// Blackman-Harris pixel filter of Blender's width (Cycles' default 1.5 px), applied
// by filter importance sampling: each sample lands at an offset drawn from the
// filter, and counts with weight 1 in its own pixel. This is what Cycles does, so
// images compare pixel for pixel, and no sample touches a neighbour's pixel
// (which keeps per-pixel accumulation free of locks and deterministic).
// Cycles 3.4 (scene/film.cpp, filter_table) doubles the width for Blackman-Harris:
// a "1.5 px" filter reaches 1.5 px either side of the pixel centre. So does this one.
// (A filter half as wide sums to far from 1 over the pixel lattice: a sub-pixel
// highlight, e.g. a 1 cm lamp seen in a mirror, then lost up to 85% of its energy.)
#pragma once
#include <array>
#include <vector>
#include "core/math.h"

namespace rdv {

class PixelFilter {
 public:
  // Blender's filter width, clamped to [1e-3, kMaxWidth] pixels.
  explicit PixelFilter(float width = 1.5f);
  static constexpr float kMaxWidth = 10.0f;
  // Pixels one axis of the filter can cover (splatting keeps their weights on the stack).
  static constexpr int kMaxTaps = 2 * int(kMaxWidth) + 2;
  float width() const { return width_; }
  // Half the support: the filter is non-zero for |x| < radius() = width().
  float radius() const { return width_; }
  // Cycles' filter_func_blackman_harris over its doubled width, x in [-width, width].
  float evaluate(float x) const;
  // Offset from the pixel centre along one axis (the filter is separable).
  float sample(float u) const;
  // The density sample() draws from (normalised 1D).
  float pdf(float x) const;
  float integral() const { return integral_; }

 private:
  float width_;
  static constexpr int kTableSize = 1024, kGuideSize = 1024;
  std::vector<float> cdf_;  // tabulated, kTableSize + 1 entries
  std::array<int, kGuideSize> guide_;  // where sample() starts its search, per cell of u
  float integral_ = 1;
};

}  // namespace rdv
