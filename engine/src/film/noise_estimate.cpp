#include "film/noise_estimate.h"
#include "film/image_error.h"
#include <algorithm>
#include <cmath>
#include <limits>

namespace rdv {

bool pixel_relative_variance(const PixelSum &pixel, const HalfSum &half, const SplatSums &splats, const SplatSums &half_splats,
                             const FrameState &frame, double *relative_variance) {
  *relative_variance = 0;
  const double paths_b = frame.half_splats.paths, paths_a = frame.splats.paths - paths_b;
  const bool has_splats = frame.splats.paths > 0;
  if (has_splats && !(paths_a > 0 && paths_b > 0)) return false;
  const double scale = frame.splat_scale;
  const double scale_a = has_splats ? frame.splats.numerator / paths_a : 0.0;
  const double scale_b = has_splats ? frame.half_splats.numerator / paths_b : 0.0;
  const double n = pixel.count;
  double f;  // half B's share of the samples
  double a[3], b[3], full[3];
  // MLT with direct light left to the path tracer: its camera samples make halves of their
  // own, independent of the chains' (their variances add: camera_variance).
  double camera_variance[3] = {0, 0, 0};
  if (frame.split == HalfSplit::CameraSamples) {
    const double nb = half.count, na = n - nb;
    if (!(na > 0 && nb > 0)) return false;
    f = nb / n;
    for (int c = 0; c < 3; ++c) {
      a[c] = (pixel.sample[c] - half.sample[c]) / na + (splats[c] - half_splats[c]) * scale_a;
      b[c] = half.sample[c] / nb + half_splats[c] * scale_b;
      full[c] = pixel.sample[c] / n + splats[c] * scale;
    }
  } else if (frame.split == HalfSplit::Splats) {
    if (!has_splats) return false;
    f = paths_b / frame.splats.paths;
    const double nb = half.count, na = n - nb;
    const bool camera_halves = na > 0 && nb > 0;
    const double fc = camera_halves ? nb / n : 0.0;
    for (int c = 0; c < 3; ++c) {
      // Camera samples without halves (the first-hit pass's, L = 0) are shared by both.
      const double camera = n > 0 ? pixel.sample[c] / n : 0.0;
      if (camera_halves) {
        const double d = (pixel.sample[c] - half.sample[c]) / na - half.sample[c] / nb;
        camera_variance[c] = d * d * fc * (1 - fc);
      }
      a[c] = camera + (splats[c] - half_splats[c]) * scale_a;
      b[c] = camera + half_splats[c] * scale_b;
      full[c] = camera + splats[c] * scale;
    }
  } else {
    return false;
  }
  double sum = 0;
  for (int c = 0; c < 3; ++c) {
    const double d = a[c] - b[c], square = full[c] * full[c];
    const double variance = d * d * f * (1 - f) + camera_variance[c] + frame.scale_relative_variance * square;
    // E[I^2] = ref^2 + Var(I): I^2 - variance estimates the reference's square. I^2
    // alone would hide a firefly in a dark pixel (its own brightness in the denominator),
    // the very error the metric weighs most. That estimate (A B for equal halves) is
    // unbiased but grows with an outlier in one half (A = r + 2e: r^2 + 2 e r), so a
    // stuck Metropolis chain or a firefly in a lit pixel still divided its own error
    // down ~7x (caustic.json, pssmlt). Where the halves differ by more than 2x, the
    // dimmer half bounds it: at most 2 min(A, B)^2, which ordinary noise rarely reaches.
    const double lower = std::min(a[c], b[c]);
    const double reference_square = std::min(std::max(0.0, square - variance), 4 * lower * lower);
    sum += variance / (reference_square + kRelativeMseEpsilon);
  }
  *relative_variance = sum / 3;
  return std::isfinite(*relative_variance);
}

double Film::relative_mse_estimate() const {
  std::lock_guard<std::mutex> frame(frame_mutex_);
  if (state_.split == HalfSplit::None || !has_halves()) return -1;
  double sum = 0;
  for (int y = region_.y0; y < region_.y1; ++y) {
    for (int x = region_.x0; x < region_.x1; ++x) {
      const size_t i = index(x, y);
      double v;
      if (!pixel_relative_variance(pixels_[i], half_pixels_[i], splats_[i], half_splats_[i], state_, &v))
        return std::numeric_limits<double>::infinity();
      sum += v;
    }
  }
  return sum / (double(region_.width()) * double(region_.height()));
}

size_t Film::mark_converged(double threshold, std::vector<uint8_t> &converged) const {
  const int w = region_.width(), h = region_.height();
  converged.resize(size_t(width_) * height_, 0);
  if (!has_halves()) return 0;
  std::vector<double> variance(size_t(w) * h);
  std::vector<uint8_t> valid(size_t(w) * h);
  {
    std::lock_guard<std::mutex> frame(frame_mutex_);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const size_t i = index(region_.x0 + x, region_.y0 + y), j = size_t(y) * w + x;
        valid[j] = pixel_relative_variance(pixels_[i], half_pixels_[i], splats_[i], half_splats_[i], state_, &variance[j]);
      }
  }
  const double limit = threshold * threshold;
  size_t marked = 0;
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const size_t i = index(region_.x0 + x, region_.y0 + y);
      if (!converged[i]) {
        double sum = 0;
        int n = 0;
        bool all_valid = true;
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx) {
            const int nx = x + dx, ny = y + dy;
            if (nx < 0 || ny < 0 || nx >= w || ny >= h) continue;
            const size_t j = size_t(ny) * w + nx;
            all_valid = all_valid && valid[j];
            sum += variance[j];
            ++n;
          }
        if (all_valid && sum <= limit * n) converged[i] = 1;
      }
      marked += converged[i];
    }
  }
  return marked;
}

}  // namespace rdv
