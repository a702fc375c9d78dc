#include "film/film.h"

namespace rdv {

Film::Film(int width, int height, Rect region)
    : width_(width), height_(height), region_(region), pixels_(size_t(width) * height),
      aovs_(size_t(width) * height), splats_(size_t(width) * height * 3) {
  for (auto &s : splats_) s.store(0.0f, std::memory_order_relaxed);
}

void Film::add_splat(Vec2 raster, Color L) {
  int x = static_cast<int>(std::floor(raster.x)), y = static_cast<int>(std::floor(raster.y));
  if (x < region_.x0 || x >= region_.x1 || y < region_.y0 || y >= region_.y1) return;
  if (!is_finite(L)) return;
  size_t i = index(x, y) * 3;
  for (int c = 0; c < 3; ++c) splats_[i + c].fetch_add(L[c], std::memory_order_relaxed);
}

void Film::read(rdv_pass pass, int x, int y, int w, int h, bool top_down, float *out) const {
  int channels = rdv_pass_channels(pass);
  float splat_scale = splat_scale_.load(std::memory_order_relaxed);
  for (int row = 0; row < h; ++row) {
    int py = y + row;
    // Blender's RenderResult stores rows bottom-up: image row py is output row h-1-row.
    float *dst = out + size_t(top_down ? row : h - 1 - row) * w * channels;
    for (int col = 0; col < w; ++col, dst += channels) {
      int px = x + col;
      size_t i = index(px, py);
      const Pixel &p = pixels_[i];
      const Aov &a = aovs_[i];
      float n = p.count;
      switch (pass) {
        case RDV_PASS_COMBINED: {
          Color c = n > 0 ? p.sum / n : Color(0.0f);
          for (int k = 0; k < 3; ++k) c[k] += splat_scale * splats_[3 * i + k].load(std::memory_order_relaxed);
          dst[0] = c.x; dst[1] = c.y; dst[2] = c.z; dst[3] = 1.0f;
          break;
        }
        case RDV_PASS_DEPTH: dst[0] = a.depth; break;
        case RDV_PASS_NORMAL: {
          float len = length(a.normal);
          Vec3 v = len > 0 ? a.normal / len : Vec3(0.0f);
          dst[0] = v.x; dst[1] = v.y; dst[2] = v.z;
          break;
        }
        case RDV_PASS_ALBEDO: {
          Color c = n > 0 ? a.albedo / n : Color(0.0f);
          dst[0] = c.x; dst[1] = c.y; dst[2] = c.z;
          break;
        }
      }
    }
  }
}

}  // namespace rdv
