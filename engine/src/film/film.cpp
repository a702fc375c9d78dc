#include "film/film.h"
#include "film/noise_estimate.h"
#include <algorithm>
#include <array>
#include <cmath>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

namespace rdv {

static_assert(StrategyPasses::count_for(StrategyPasses::kMaxDepth) == RDV_PASS_STRATEGY_LAST - RDV_PASS_STRATEGY_FIRST + 1,
              "the C ABI's range of strategy passes holds those of the deepest setting");

Film::Film(int width, int height, Rect region, bool halves, bool light_passes, bool data_passes,
           int strategy_max_depth, bool denoising_passes, const ShaderAovs &shader_aovs, const Cryptomatte &cryptomatte)
    : width_(width), height_(height), region_(region), pixels_(size_t(width) * height),
      aovs_(size_t(width) * height), splats_(size_t(width) * height),
      half_pixels_(halves ? size_t(width) * height : 0), half_splats_(halves ? size_t(width) * height : 0),
      light_(light_passes ? size_t(width) * height : 0), light_splats_(light_passes ? size_t(width) * height : 0),
      data_passes_(data_passes), denoising_(denoising_passes ? size_t(width) * height : 0), shader_aovs_(shader_aovs),
      shader_aov_sums_(size_t(width) * height * size_t(shader_aovs.channels)), cryptomatte_(cryptomatte),
      crypto_(size_t(width) * height * size_t(cryptomatte.slots_per_pixel())), strategies_{strategy_max_depth},
      strategy_(size_t(width) * height * size_t(strategies_.count())),
      strategy_splats_(size_t(width) * height * size_t(strategies_.splat_count())) {}

size_t Film::bytes_per_pixel(bool halves, bool light_passes, int strategy_max_depth, bool denoising_passes,
                             int shader_aov_channels, int crypto_slots) {
  const StrategyPasses strategies{strategy_max_depth};
  return sizeof(PixelSum) + sizeof(PixelAov) + sizeof(SplatSums) + size_t(shader_aov_channels) * sizeof(double) +
         size_t(crypto_slots) * sizeof(CryptoSlot) +
         (halves ? sizeof(HalfSum) + sizeof(SplatSums) : 0) +
         (light_passes ? sizeof(LightPassSums) + sizeof(LightSplatSums) : 0) +
         (denoising_passes ? sizeof(DenoisingSums) : 0) +
         size_t(strategies.count() + strategies.splat_count()) * sizeof(StrategySums);
}

void Film::take_tile(const Rect &rect, FilmTile &tile) const {
  tile.rect_ = rect;
  size_t n = size_t(rect.width()) * size_t(rect.height());
  tile.pixels_.resize(n);
  tile.halves_.resize(has_halves() ? n : 0);
  tile.aovs_.resize(n);
  tile.light_.resize(has_light_passes() ? n : 0);
  tile.denoising_.resize(has_denoising_passes() ? n : 0);
  const size_t na = size_t(shader_aovs_.channels);  // shader AOV sums per pixel
  tile.aov_channels_ = int(na);
  tile.shader_aovs_.resize(n * na);
  const size_t nc = size_t(cryptomatte_.slots_per_pixel());  // Cryptomatte slots per pixel
  tile.crypto_slots_ = int(nc);
  tile.crypto_.resize(n * nc);
  tile.catcher_.resize(has_shadow_catcher() ? n : 0);
  const size_t ns = size_t(strategies_.count());  // strategy sums per pixel
  tile.strategy_count_ = int(ns);
  tile.strategy_.resize(n * ns);
  std::lock_guard<std::mutex> frame(frame_mutex_);
  for (int y = rect.y0; y < rect.y1; ++y) {
    std::copy_n(&pixels_[index(rect.x0, y)], rect.width(), &tile.pixels_[tile.index(rect.x0, y)]);
    if (has_halves())
      std::copy_n(&half_pixels_[index(rect.x0, y)], rect.width(), &tile.halves_[tile.index(rect.x0, y)]);
    std::copy_n(&aovs_[index(rect.x0, y)], rect.width(), &tile.aovs_[tile.index(rect.x0, y)]);
    if (has_light_passes())
      std::copy_n(&light_[index(rect.x0, y)], rect.width(), &tile.light_[tile.index(rect.x0, y)]);
    if (has_denoising_passes())
      std::copy_n(&denoising_[index(rect.x0, y)], rect.width(), &tile.denoising_[tile.index(rect.x0, y)]);
    if (na)
      std::copy_n(&shader_aov_sums_[index(rect.x0, y) * na], rect.width() * na, &tile.shader_aovs_[tile.index(rect.x0, y) * na]);
    if (nc) std::copy_n(&crypto_[index(rect.x0, y) * nc], rect.width() * nc, &tile.crypto_[tile.index(rect.x0, y) * nc]);
    if (has_shadow_catcher())
      std::copy_n(&catcher_[index(rect.x0, y)], rect.width(), &tile.catcher_[tile.index(rect.x0, y)]);
    if (ns)
      std::copy_n(&strategy_[index(rect.x0, y) * ns], rect.width() * ns, &tile.strategy_[tile.index(rect.x0, y) * ns]);
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
    if (has_light_passes())
      std::copy_n(&tile.light_[tile.index(rect.x0, y)], rect.width(), &light_[index(rect.x0, y)]);
    if (has_denoising_passes())
      std::copy_n(&tile.denoising_[tile.index(rect.x0, y)], rect.width(), &denoising_[index(rect.x0, y)]);
    if (const size_t na = size_t(shader_aovs_.channels))
      std::copy_n(&tile.shader_aovs_[tile.index(rect.x0, y) * na], rect.width() * na, &shader_aov_sums_[index(rect.x0, y) * na]);
    if (const size_t nc = size_t(cryptomatte_.slots_per_pixel()))
      std::copy_n(&tile.crypto_[tile.index(rect.x0, y) * nc], rect.width() * nc, &crypto_[index(rect.x0, y) * nc]);
    if (has_shadow_catcher())
      std::copy_n(&tile.catcher_[tile.index(rect.x0, y)], rect.width(), &catcher_[index(rect.x0, y)]);
    if (const size_t ns = size_t(strategies_.count()))
      std::copy_n(&tile.strategy_[tile.index(rect.x0, y) * ns], rect.width() * ns, &strategy_[index(rect.x0, y) * ns]);
  }
}

// The pixels whose filter covers `raster` (inclusive bounds), in rows [row0, row1) only
// (a band of the region's rows): none when x1 < x0 or y1 < y0.
struct SplatPixels {
  int x0, x1, y0, y1;
  bool empty() const { return x1 < x0 || y1 < y0; }
};
static SplatPixels splat_pixels(Vec2 raster, const PixelFilter &filter, const Rect &region, int row0, int row1) {
  const float radius = filter.radius();
  return {std::max(region.x0, int(std::floor(raster.x - radius - 0.5f))),
          std::min(region.x1 - 1, int(std::ceil(raster.x + radius - 0.5f))),
          std::max(std::max(region.y0, row0), int(std::floor(raster.y - radius - 0.5f))),
          std::min(std::min(region.y1, row1) - 1, int(std::ceil(raster.y + radius - 0.5f)))};
}

// Calls add(pixel index, weight) for every pixel of `pixels` (splat_pixels of `raster`),
// with the same normalised Blackman-Harris weights filter importance sampling gives
// camera samples.
template <class Add>
static void splat_footprint(Vec2 raster, const SplatPixels &pixels, const PixelFilter &filter, int width,
                            const Add &add) {
  float norm = 1.0f / (filter.integral() * filter.integral());
  const auto [x0, x1, y0, y1] = pixels;
  // The filter is separable: its weights along x are the same for every row.
  std::array<float, PixelFilter::kMaxTaps> wx;
  for (int x = x0; x <= x1; ++x) wx[x - x0] = filter.evaluate(raster.x - (x + 0.5f));
  for (int y = y0; y <= y1; ++y) {
    float wy = filter.evaluate(raster.y - (y + 0.5f));
    if (wy <= 0) continue;
    for (int x = x0; x <= x1; ++x) {
      float w = wy * wx[x - x0];
      if (w > 0) add(size_t(y) * size_t(width) + size_t(x), w * norm);
    }
  }
}

static void add_to(std::array<double, 3> &sum, const Color &c) {
  sum[0] += c.x;
  sum[1] += c.y;
  sum[2] += c.z;
}

void Film::for_each_row_band(const std::function<void(int, int)> &band) {
  const int rows = region_.height();
  // A few bands per thread, so one band with the image's bright spot does not hold the rest.
  const int bands = std::clamp(4 * tbb::this_task_arena::max_concurrency(), 1, std::max(rows, 1));
  if (bands == 1) {
    band(region_.y0, region_.y1);
    return;
  }
  tbb::parallel_for(0, bands, [&](int b) {
    band(region_.y0 + int(int64_t(rows) * b / bands), region_.y0 + int(int64_t(rows) * (b + 1) / bands));
  });
}

void Film::add_splat(Vec2 raster, Color L, const PixelFilter &filter, bool half_b, uint8_t strategy,
                     const SplatLightPass &light_pass, const SlotShare *shares, CatcherSplat catcher, int y0,
                     int y1) {
  if (!is_finite(L)) return;
  // Each band of rows sees every splat (add_splats): one outside it costs only this.
  const SplatPixels pixels = splat_pixels(raster, filter, region_, y0, y1);
  if (pixels.empty()) return;
  // BDPT in a scene with a shadow catcher (shadow_catcher_passes.h): a copy's splat is the
  // catcher pass's alone (pssmlt's camera-sample matte the matte's alone; a split camera
  // sample's copy also counts a split where it lands); the others are Combined's, some the
  // matte's too.
  if (catcher == CatcherSplat::Pass || catcher == CatcherSplat::Matte || catcher == CatcherSplat::SplitPass) {
    if (has_shadow_catcher())
      splat_footprint(raster, pixels, filter, width_, [&](size_t i, float w) {
        add_to(catcher == CatcherSplat::Matte ? catcher_[i].matte_splats : catcher_[i].catcher_splats, L * w);
        if (catcher == CatcherSplat::SplitPass) catcher_[i].add_split();
      });
    return;
  }
  const bool to_matte = catcher == CatcherSplat::CombinedAndMatte && has_shadow_catcher();
  const bool half = half_b && has_halves();
  // Its strategy pass's and light passes' splat sums, when the film keeps them: one
  // footprint for all.
  const int slot = strategy < strategies_.count() ? strategies_.splat_slot(strategy) : -1;
  const size_t slots = size_t(strategies_.splat_count());
  // The slots with a share, found once per splat (most splats have one): the kinds of
  // its first scattering vertex, or the shares it carries (Metropolis).
  int n_shares = 0;
  std::array<Color, kLightPassSlots> share_L;
  std::array<uint8_t, kLightPassSlots> share_slot;
  if (light_pass.on && has_light_passes()) {
    if (light_pass.shares > 0) {
      for (int k = 0; k < std::min<int>(light_pass.shares, kLightPassSlots); ++k) {
        share_L[n_shares] = shares[k].L;
        share_slot[n_shares++] = shares[k].slot;
      }
    } else {
      for (int k = 0; k < kPassKinds; ++k)
        if (light_pass.first.w[k] > 0) {
          share_L[n_shares] = L * light_pass.first.w[k];
          share_slot[n_shares++] = uint8_t(light_pass_slot(k, light_pass.indirect));
        }
    }
  }
  splat_footprint(raster, pixels, filter, width_, [&](size_t i, float w) {
    Color c = L * w;
    add_to(splats_[i], c);
    if (half) add_to(half_splats_[i], c);
    if (slot >= 0) add_to(strategy_splats_[i * slots + size_t(slot)], c);
    for (int k = 0; k < n_shares; ++k) add_to(light_splats_[i][share_slot[k]], share_L[k] * w);
    if (to_matte) add_to(catcher_[i].matte_splats, c);
  });
}

void Film::keep_shadow_catcher(const CatcherDisplay &display) {
  catcher_display_ = display;
  catcher_.assign(size_t(width_) * size_t(height_), CatcherSums{});
}

void Film::read_strategy_pass(int k, size_t i, float *dst) const {
  const double n = pixels_[i].count;
  const StrategySums &sum = strategy_[i * size_t(strategies_.count()) + size_t(k)];
  const int slot = strategies_.splat_slot(k);
  for (int c = 0; c < 3; ++c) {
    double m = n > 0 ? sum[c] / n : 0.0;
    if (slot >= 0) m += strategy_splats_[i * size_t(strategies_.splat_count()) + size_t(slot)][c] * state_.splat_scale;
    dst[c] = float(m);
  }
}

void Film::read_light_pass(rdv_pass pass, size_t i, float *dst) const {
  const LightPassSums &p = light_[i];
  const double n = pixels_[i].count;
  const double splat_scale = state_.splat_scale;
  // The pass's mean: camera samples' sums over their count plus the splats.
  auto mean = [&](int slot) {
    std::array<double, 3> m;
    for (int c = 0; c < 3; ++c) m[c] = (n > 0 ? p.light[slot][c] / n : 0.0) + light_splats_[i][slot][c] * splat_scale;
    return m;
  };
  auto color_mean = [&](int kind) {
    std::array<double, 3> m;
    for (int c = 0; c < 3; ++c) m[c] = n > 0 ? p.color[kind][c] / n : 0.0;
    return m;
  };
  Color out(0.0f);
  switch (pass) {
    case RDV_PASS_EMISSION:
    case RDV_PASS_ENVIRONMENT: {
      std::array<double, 3> m = mean(pass == RDV_PASS_EMISSION ? kEmissionSlot : kEnvironmentSlot);
      out = Color(float(m[0]), float(m[1]), float(m[2]));
      break;
    }
    case RDV_PASS_DIFFUSE_COLOR:
    case RDV_PASS_GLOSSY_COLOR:
    case RDV_PASS_TRANSMISSION_COLOR: {
      std::array<double, 3> m = color_mean((pass - RDV_PASS_DIFFUSE_COLOR) / 3);
      out = Color(float(m[0]), float(m[1]), float(m[2]));
      break;
    }
    case RDV_PASS_VOLUME_DIRECT:
    case RDV_PASS_VOLUME_INDIRECT: {
      std::array<double, 3> m = mean(light_pass_slot(3, pass == RDV_PASS_VOLUME_INDIRECT));
      out = Color(float(m[0]), float(m[1]), float(m[2]));
      break;
    }
    default: {  // Direct / Indirect of a kind with a colour: divided by it, as Cycles shows them
      const int offset = pass - RDV_PASS_DIFFUSE_DIRECT;  // kinds 3 passes apart: direct, indirect, color
      const int kind = offset / 3;
      out = safe_divide_even_color(mean(light_pass_slot(kind, offset % 3 == 1)), color_mean(kind));
      break;
    }
  }
  for (int c = 0; c < 3; ++c) dst[c] = out[c];
}

// Shader AOV k of the colour range (r, g, b and the share of samples that wrote it) or of the
// value range: the sums over the pixel's samples; zeros for a k the film has no such pass for.
void Film::read_shader_aov(rdv_pass pass, size_t i, double n, float *dst) const {
  const bool color = pass <= RDV_PASS_AOV_COLOR_LAST;
  const size_t k = size_t(pass - (color ? RDV_PASS_AOV_COLOR_FIRST : RDV_PASS_AOV_VALUE_FIRST));
  const int channels = color ? 4 : 1;
  if (k >= shader_aovs_.passes.size() || shader_aovs_.passes[k].color != color || !(n > 0)) {
    std::fill_n(dst, channels, 0.0f);
    return;
  }
  const double *sums = &shader_aov_sums_[i * size_t(shader_aovs_.channels) + size_t(shader_aovs_.passes[k].offset)];
  for (int c = 0; c < channels; ++c) dst[c] = float(sums[c] / n);
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
          if (has_shadow_catcher()) {  // as Blender shows it (film/shadow_catcher_passes.h)
            const CatcherSums sums = shadow_catcher::with_splats(catcher_[i], n, splat_scale);
            const std::array<double, 4> v =
                catcher_display_.pass
                    ? shadow_catcher::matte(n, sums)
                    : shadow_catcher::matte_with_shadow(shadow_catcher::with_splats(p.sample, splats_[i], n, splat_scale),
                                                        p.transparent, n, sums, catcher_display_.film_transparent);
            for (int c = 0; c < 4; ++c) dst[c] = float(v[c]);
            break;
          }
          const SplatSums &sp = splats_[i];
          for (int c = 0; c < 3; ++c) dst[c] = float((n > 0 ? p.sample[c] / n : 0.0) + sp[c] * splat_scale);
          // Coverage: what of the pixel's samples did not see the transparent background
          // or a holdout (splats land on surfaces the camera sees: they cover nothing).
          dst[3] = n > 0 ? float(std::clamp(1.0 - p.transparent / n, 0.0, 1.0)) : 1.0f;
          break;
        }
        case RDV_PASS_SHADOW_CATCHER: {
          const std::array<double, 3> f =
              has_shadow_catcher()
                  ? shadow_catcher::factor(shadow_catcher::with_splats(p.sample, splats_[i], n, splat_scale), p.transparent,
                                           n, shadow_catcher::with_splats(catcher_[i], n, splat_scale))
                  : std::array<double, 3>{1.0, 1.0, 1.0};
          for (int c = 0; c < 3; ++c) dst[c] = float(f[c]);
          break;
        }
        case RDV_PASS_SHADOW_CATCHER_MATTE: {
          const std::array<double, 4> v = has_shadow_catcher()
                                              ? shadow_catcher::matte(n, shadow_catcher::with_splats(catcher_[i], n, splat_scale))
                                              : std::array<double, 4>{0.0, 0.0, 0.0, 1.0};
          for (int c = 0; c < 4; ++c) dst[c] = float(v[c]);
          break;
        }
        case RDV_PASS_DEPTH: dst[0] = a.depth; break;
        // Data passes (film/data_passes.h): the mist from its cover, as Cycles' 1 - sum / n.
        case RDV_PASS_MIST: dst[0] = n > 0 ? float(std::clamp(1.0 - a.mist_cover / n, 0.0, 1.0)) : 1.0f; break;
        case RDV_PASS_OBJECT_INDEX: dst[0] = a.object_index; break;
        case RDV_PASS_MATERIAL_INDEX: dst[0] = a.material_index; break;
        case RDV_PASS_NORMAL: {
          double len = std::sqrt(a.normal[0] * a.normal[0] + a.normal[1] * a.normal[1] + a.normal[2] * a.normal[2]);
          for (int c = 0; c < 3; ++c) dst[c] = len > 0 ? float(a.normal[c] / len) : 0.0f;
          break;
        }
        case RDV_PASS_ALBEDO: {
          for (int c = 0; c < 3; ++c) dst[c] = n > 0 ? float(a.albedo[c] / n) : 0.0f;
          break;
        }
        // Denoising data (film/denoising_passes.h): the samples' means (zeros without them).
        case RDV_PASS_DENOISING_NORMAL:
        case RDV_PASS_DENOISING_ALBEDO: {
          const bool normal = pass == RDV_PASS_DENOISING_NORMAL;
          for (int c = 0; c < 3; ++c)
            dst[c] = has_denoising_passes() && n > 0
                         ? float((normal ? denoising_[i].normal[c] : denoising_[i].albedo[c]) / n)
                         : 0.0f;
          break;
        }
        case RDV_PASS_DENOISING_DEPTH: dst[0] = has_denoising_passes() && n > 0 ? float(denoising_[i].depth / n) : 0.0f; break;
        case RDV_PASS_NOISE: {
          double v;
          dst[0] = has_halves() && pixel_relative_variance(p, half_pixels_[i], splats_[i], half_splats_[i], state_, &v)
                       ? float(std::sqrt(v))
                       : 0.0f;
          break;
        }
        default:
          if (pass >= RDV_PASS_AOV_COLOR_FIRST && pass <= RDV_PASS_AOV_VALUE_LAST) {
            read_shader_aov(pass, i, n, dst);
          } else if (pass >= RDV_PASS_CRYPTOMATTE_FIRST && pass <= RDV_PASS_CRYPTOMATTE_LAST) {
            const int k = pass - RDV_PASS_CRYPTOMATTE_FIRST;
            const size_t slots = size_t(cryptomatte_.slots_per_pixel());
            if (slots) read_crypto_pass(cryptomatte_, &crypto_[i * slots], Cryptomatte::Kind(k / Cryptomatte::kMaxPassesPerKind),
                                        k % Cryptomatte::kMaxPassesPerKind, n, dst);
            else std::fill_n(dst, 4, 0.0f);
          } else if (pass >= RDV_PASS_STRATEGY_FIRST) {
            if (pass - RDV_PASS_STRATEGY_FIRST < strategies_.count()) read_strategy_pass(pass - RDV_PASS_STRATEGY_FIRST, i, dst);
            else std::fill_n(dst, channels, 0.0f);
          } else if (has_light_passes()) read_light_pass(pass, i, dst);
          else std::fill_n(dst, channels, 0.0f);
          break;
      }
    }
  }
}

}  // namespace rdv
