// The film: per-pixel sample accumulation (owned by one thread per pixel at a time,
// so no locks and a deterministic sum), a separate splat buffer that any thread adds
// to anywhere (light tracing, BDPT's t = 1 strategies, MLT), and first-hit AOVs.
#pragma once
#include <atomic>
#include <mutex>
#include <vector>
#include "core/math.h"
#include "film/pixel_filter.h"
#include "rendezvous.h"

namespace rdv {

struct Rect {
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;  // [x0, x1) x [y0, y1), pixels, (0,0) top-left
  int width() const { return x1 - x0; }
  int height() const { return y1 - y0; }
};

class Film {
 public:
  Film(int width, int height, Rect region);
  // What one pixel costs (samples, splats, AOVs): for the memory check before a film is made.
  static size_t bytes_per_pixel();
  int width() const { return width_; }
  int height() const { return height_; }
  const Rect &region() const { return region_; }

  void add_sample(int x, int y, Color L) {
    Pixel &p = pixels_[index(x, y)];
    p.sum += L;
    p.count += 1;
  }
  // Spreads L over the pixels whose filter covers `raster`, with the same normalised
  // Blackman-Harris weights filter importance sampling gives camera samples, so that
  // splatted and sampled estimates converge to the same image. Not thread-safe: the
  // session applies splats in a fixed order after each pass (deterministic sums).
  void add_splat(Vec2 raster, Color L, const PixelFilter &filter);
  void add_first_hit(int x, int y, float depth, Vec3 normal, Color albedo) {
    Aov &a = aovs_[index(x, y)];
    a.depth = std::min(a.depth, depth);
    a.normal += normal;
    a.albedo += albedo;
  }
  // The integrator that makes splats knows their normalisation (samples per pixel over
  // the whole image, or MLT's b / mutations per pixel) and sets it with them.
  void set_splat_scale(double s) { splat_scale_.store(s, std::memory_order_relaxed); }
  // Held while splats of a pass and their scale are applied, and while the frame is
  // read: a progressive read never sees new splats with the old scale.
  std::mutex &frame_mutex() const { return frame_mutex_; }

  // Rectangle of a pass, row order top-down or bottom-up.
  void read(rdv_pass pass, int x, int y, int w, int h, bool top_down, float *out) const;

 private:
  struct Pixel { Color sum{0.0f}; float count = 0; };
  struct Aov { float depth = 1e10f; Vec3 normal{0.0f}; Color albedo{0.0f}; };
  // Splat sums in double: MLT adds millions of splats to a pixel, and a float sum
  // stops growing once each splat is below its rounding step.
  struct SplatSum { double r = 0, g = 0, b = 0; };
  size_t index(int x, int y) const { return size_t(y) * width_ + x; }
  int width_, height_;
  Rect region_;
  std::vector<Pixel> pixels_;
  std::vector<Aov> aovs_;
  std::vector<SplatSum> splats_;
  std::atomic<double> splat_scale_{0.0};
  mutable std::mutex frame_mutex_;
};

}  // namespace rdv
