#include "film/film.h"
#include "film/noise_estimate.h"
#include <algorithm>
#include <array>
#include <cmath>

namespace rdv {

Film::Film(int width, int height, Rect region, bool halves)
    : width_(width), height_(height), region_(region), pixels_(size_t(width) * height),
      aovs_(size_t(width) * height), splats_(size_t(width) * height),
      half_pixels_(halves ? size_t(width) * height : 0), half_splats_(halves ? size_t(width) * height : 0) {}

size_t Film::bytes_per_pixel(bool halves) {
  return sizeof(PixelSum) + sizeof(PixelAov) + sizeof(SplatSums) +
         (halves ? sizeof(HalfSum) + sizeof(SplatSums) : 0);
}

void Film::take_tile(const Rect &rect, FilmTile &tile) const {
  tile.rect_ = rect;
  size_t n = size_t(rect.width()) * size_t(rect.height());
  tile.pixels_.resize(n);
  tile.halves_.resize(has_halves() ? n : 0);
  tile.aovs_.resize(n);
  std::lock_guard<std::mutex> frame(frame_mutex_);
  for (int y = rect.y0; y < rect.y1; ++y) {
    std::copy_n(&pixels_[index(rect.x0, y)], rect.width(), &tile.pixels_[tile.index(rect.x0, y)]);
    if (has_halves())
      std::copy_n(&half_pixels_[index(rect.x0, y)], rect.width(), &tile.halves_[tile.index(rect.x0, y)]);
    std::copy_n(&aovs_[index(rect.x0, y)], rect.width(), &tile.aovs_[tile.index(rect.x0, y)]);
  }
}

void Film::put_tile(const FilmTile &tile) {
  const Rect &rect = tile.rect_;
  std::lock_guard<std::mutex> frame(frame_mutex_);
  for (int y = rect.y0; y < rect.y1; ++y) {
    std::copy_n(&tile.pixels_[tile.index(rect.x0, y)], rect.width(), &pixels_[index(rect.x0, y)]);
    if (has_halves())
      std::copy_n(&tile.halves_[tile.index(rect.x0, y)], rect.width(), &half_pixels_[index(rect.x0, y)]);
    std::copy_n(&tile.aovs_[tile.index(rect.x0, y)], rect.width(), &aovs_[index(rect.x0, y)]);
  }
}

void Film::add_splat(Vec2 raster, Color L, const PixelFilter &filter, bool half_b) {
  if (!is_finite(L)) return;
  float radius = filter.radius();
  float norm = 1.0f / (filter.integral() * filter.integral());
  int x0 = std::max(region_.x0, int(std::floor(raster.x - radius - 0.5f)));
  int x1 = std::min(region_.x1 - 1, int(std::ceil(raster.x + radius - 0.5f)));
  int y0 = std::max(region_.y0, int(std::floor(raster.y - radius - 0.5f)));
  int y1 = std::min(region_.y1 - 1, int(std::ceil(raster.y + radius - 0.5f)));
  if (x1 < x0) return;
  // The filter is separable: its weights along x are the same for every row.
  std::array<float, PixelFilter::kMaxTaps> wx;
  for (int x = x0; x <= x1; ++x) wx[x - x0] = filter.evaluate(raster.x - (x + 0.5f));
  for (int y = y0; y <= y1; ++y) {
    float wy = filter.evaluate(raster.y - (y + 0.5f));
    if (wy <= 0) continue;
    for (int x = x0; x <= x1; ++x) {
      float w = wy * wx[x - x0];
      if (w > 0) {
        Color c = L * (w * norm);
        SplatSums &sum = splats_[index(x, y)];
        sum[0] += c.x;
        sum[1] += c.y;
        sum[2] += c.z;
        if (half_b && has_halves()) {
          SplatSums &half = half_splats_[index(x, y)];
          half[0] += c.x;
          half[1] += c.y;
          half[2] += c.z;
        }
      }
    }
  }
}

void Film::read(rdv_pass pass, int x, int y, int w, int h, bool top_down, float *out, FrameState *state) const {
  int channels = rdv_pass_channels(pass);
  std::lock_guard<std::mutex> frame(frame_mutex_);
  if (state) *state = state_;
  const double splat_scale = state_.splat_scale;
  for (int row = 0; row < h; ++row) {
    int py = y + row;
    // Blender's RenderResult stores rows bottom-up: image row py is output row h-1-row.
    float *dst = out + size_t(top_down ? row : h - 1 - row) * w * channels;
    for (int col = 0; col < w; ++col, dst += channels) {
      int px = x + col;
      size_t i = index(px, py);
      const PixelSum &p = pixels_[i];
      const PixelAov &a = aovs_[i];
      const double n = p.count;
      switch (pass) {
        case RDV_PASS_COMBINED: {
          const SplatSums &sp = splats_[i];
          for (int c = 0; c < 3; ++c) dst[c] = float((n > 0 ? p.sample[c] / n : 0.0) + sp[c] * splat_scale);
          // Coverage: what of the pixel's samples did not see the transparent background
          // or a holdout (splats land on surfaces the camera sees: they cover nothing).
          dst[3] = n > 0 ? float(std::clamp(1.0 - p.transparent / n, 0.0, 1.0)) : 1.0f;
          break;
        }
        case RDV_PASS_DEPTH: dst[0] = a.depth; break;
        case RDV_PASS_NORMAL: {
          double len = std::sqrt(a.normal[0] * a.normal[0] + a.normal[1] * a.normal[1] + a.normal[2] * a.normal[2]);
          for (int c = 0; c < 3; ++c) dst[c] = len > 0 ? float(a.normal[c] / len) : 0.0f;
          break;
        }
        case RDV_PASS_ALBEDO: {
          for (int c = 0; c < 3; ++c) dst[c] = n > 0 ? float(a.albedo[c] / n) : 0.0f;
          break;
        }
        case RDV_PASS_NOISE: {
          double v;
          dst[0] = has_halves() && pixel_relative_variance(p, half_pixels_[i], splats_[i], half_splats_[i], state_, &v)
                       ? float(std::sqrt(v))
                       : 0.0f;
          break;
        }
      }
    }
  }
}

}  // namespace rdv
