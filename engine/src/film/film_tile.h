// A rectangle of the film that one render thread adds camera samples and first-hit
// AOVs to (pbrt-v3's FilmTile): no locks and no sharing in the sample loop. Film::
// take_tile fills it with the film's sums, so samples add up in the same order as if
// they went to the film directly (the same image on any thread count), and
// Film::put_tile publishes it whole: a progressive read never sees half a sample.
#pragma once
#include <algorithm>
#include <array>
#include <cstdint>
#include <vector>
#include "core/math.h"
#include "film/data_passes.h"
#include "film/light_passes.h"
#include "film/shadow_catcher_passes.h"
#include "film/strategy_passes.h"

namespace rdv {

struct Rect {
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;  // [x0, x1) x [y0, y1), pixels, (0,0) top-left
  int width() const { return x1 - x0; }
  int height() const { return y1 - y0; }
};

// A pixel's camera samples: their sum (double: render parts add up to the whole
// render's sums, film/render_part.h) and count. transparent: the samples' transparency
// (integrators/film_alpha.h; alpha = 1 - transparent / count), 0 with an opaque film; a
// float in the count's padding, so the film costs no more (alpha needs no more precision:
// 2^24 samples of 1 still sum exactly).
struct PixelSum {
  std::array<double, 3> sample{};
  uint32_t count = 0;
  float transparent = 0;
};
static_assert(sizeof(PixelSum) == 32, "the transparency sum lives in the count's padding");

// The same for the samples of a pixel's half B: with the rest, two independent half
// images whose difference estimates the noise (film/noise_estimate.h). Kept apart so
// that a render that estimates no noise neither stores nor copies them.
struct HalfSum {
  std::array<double, 3> sample{};
  uint32_t count = 0;
};

// First-hit AOVs: nearest depth, summed normals and albedos (averaged by the count);
// the data passes (film/data_passes.h): the samples' summed mist cover (double, as the
// other sums: render parts merge to the whole render's) and the pass indices of the
// pixel's sample 0 (0 in every other sample, so render parts add up to them).
struct PixelAov {
  float depth = 1e10f;
  float object_index = 0;
  std::array<double, 3> normal{}, albedo{};
  double mist_cover = 0;
  float material_index = 0;
};

class FilmTile {
 public:
  const Rect &rect() const { return rect_; }
  void add_sample(int x, int y, Color L, bool half_b, float transparency = 0) {
    PixelSum &p = pixels_[index(x, y)];
    p.transparent += transparency;
    p.sample[0] += L.x;
    p.sample[1] += L.y;
    p.sample[2] += L.z;
    p.count += 1;
    if (half_b) {  // only when the film keeps halves (Film::has_halves)
      HalfSum &h = halves_[index(x, y)];
      h.sample[0] += L.x;
      h.sample[1] += L.y;
      h.sample[2] += L.z;
      h.count += 1;
    }
  }
  // Light passes (film/light_passes.h): only when the film keeps them (Film::has_light_passes).
  void add_light_passes(int x, int y, const LightPassSample &sample) { light_[index(x, y)].add(sample); }
  // Strategy passes (film/strategy_passes.h): the sample's share in each of the film's
  // strategy_count passes; only when the film keeps them.
  void add_strategy_passes(int x, int y, const Color *sample) {
    StrategySums *sums = &strategy_[index(x, y) * size_t(strategy_count_)];
    for (int k = 0; k < strategy_count_; ++k)
      for (int c = 0; c < 3; ++c) sums[k][c] += sample[k][c];
  }
  // first_sample: the pixel's sample 0, the one whose pass indices Cycles keeps.
  void add_data_passes(int x, int y, const DataPassSample &data, bool first_sample) {
    PixelAov &a = aovs_[index(x, y)];
    a.mist_cover += data.mist_cover;
    if (first_sample) {
      a.object_index = data.object_index;
      a.material_index = data.material_index;
    }
    if (!denoising_.empty()) denoising_[index(x, y)].add(data.denoising);  // only when the film keeps them
    if (aov_channels_ && data.aovs.active()) {  // shader AOVs (film/shader_aovs.h)
      double *sums = &shader_aovs_[index(x, y) * size_t(aov_channels_)];
      for (int c = 0; c < aov_channels_; ++c) sums[c] += data.aovs.values[c];
    }
    if (crypto_slots_ && data.crypto.active())  // Cryptomatte (film/cryptomatte.h)
      add_crypto_sample(*data.crypto.layout, &crypto_[index(x, y) * size_t(crypto_slots_)], data.crypto);
  }
  // Shadow catchers (film/shadow_catcher_passes.h): only when the film keeps them.
  void add_shadow_catcher(int x, int y, const CatcherSample &sample) { catcher_[index(x, y)].add(sample); }
  void add_first_hit(int x, int y, float depth, Vec3 normal, Color albedo) {
    PixelAov &a = aovs_[index(x, y)];
    a.depth = std::min(a.depth, depth);
    for (int c = 0; c < 3; ++c) {
      a.normal[c] += normal[c];
      a.albedo[c] += albedo[c];
    }
  }

 private:
  friend class Film;
  size_t index(int x, int y) const { return size_t(y - rect_.y0) * size_t(rect_.width()) + size_t(x - rect_.x0); }
  Rect rect_;
  std::vector<PixelSum> pixels_;
  std::vector<HalfSum> halves_;  // empty unless the film keeps halves
  std::vector<PixelAov> aovs_;
  std::vector<LightPassSums> light_;  // empty unless the film keeps light passes
  std::vector<DenoisingSums> denoising_;  // empty unless the film keeps denoising data
  std::vector<double> shader_aovs_;  // aov_channels_ per pixel (film/shader_aovs.h)
  int aov_channels_ = 0;
  std::vector<CryptoSlot> crypto_;  // crypto_slots_ per pixel (film/cryptomatte.h)
  int crypto_slots_ = 0;
  std::vector<CatcherSums> catcher_;  // empty unless the film keeps shadow catcher sums
  std::vector<StrategySums> strategy_;  // strategy_count_ per pixel (0 unless the film keeps them)
  int strategy_count_ = 0;
};

}  // namespace rdv
