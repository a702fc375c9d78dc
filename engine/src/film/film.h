// The film: per-pixel sample accumulation (render threads fill tiles of it, FilmTile),
// a splat buffer that light paths reach anywhere on (light tracing, BDPT's t = 1
// strategies, MLT), first-hit AOVs, and the frame state a read shows. Reads are safe
// while rendering: every access to the film's sums is under the frame lock, and each
// holds a whole tile or a whole pass, never a part of one.
#pragma once
#include <array>
#include <functional>
#include <mutex>
#include <vector>
#include "core/math.h"
#include "film/film_tile.h"
#include "film/pixel_filter.h"
#include "rendezvous.h"

namespace rdv {

// What the splats of a frame are: published with them after each complete pass, so a
// read scales them for exactly the passes they hold.
// How the splat sums become radiance: numerator / paths (tile integrators: the image's
// pixel count over the light paths traced; MLT: b over the mutations made).
struct SplatNormalisation {
  double numerator = 0, paths = 0;
  double scale() const { return paths > 0 ? numerator / paths : 0.0; }
};

// How a frame splits into the two independent half images that estimate its noise
// (film/noise_estimate.h): by camera sample (path, bdpt: the odd samples, each with its
// light path), by chain (MLT: the odd chains' splats), or not at all (the settings ask
// for no estimate; merged render parts have halves when every part kept its own).
enum class HalfSplit : uint8_t { None, CameraSamples, Splats };

struct FrameState {
  uint64_t pass = 0;       // complete passes published (0: none yet, no splats)
  uint32_t samples = 0;    // samples per pixel of those passes (MLT: mutations per pixel)
  double splat_scale = 0;  // their normalisation (the integrator's business)
  SplatNormalisation splats;  // splat_scale as numerator / paths (render parts merge these)
  HalfSplit split = HalfSplit::None;
  SplatNormalisation half_splats;  // the splats of half B: numerator / its paths
  // Relative variance of the image's numerator b (MLT: the whole image scales with it,
  // so its error is shared by both halves and their difference misses it).
  double scale_relative_variance = 0;
};

// Splat sums in double: MLT adds millions of splats to a pixel, and a float sum stops
// growing once each splat is below its rounding step.
using SplatSums = std::array<double, 3>;

class Film {
 public:
  // halves: keep the two half images a noise estimate needs (RenderSettings::
  // estimates_noise()); without them a frame can only be published with HalfSplit::None.
  // light_passes: keep Cycles' light passes (film/light_passes.h); without them a film
  // stores and copies nothing of them.
  // data_passes: EXR output carries Mist, Object and Material Index (film/data_passes.h;
  // the film keeps them either way).
  // strategy_max_depth: keep BDPT's strategy passes of paths up to this depth
  // (film/strategy_passes.h); -1: none, and the film stores and copies nothing of them.
  // denoising_passes: keep Cycles' denoising data (film/denoising_passes.h).
  // shader_aovs: the view layer's shader AOVs (film/shader_aovs.h); none: the film stores
  // and copies nothing of them. cryptomatte: the same for Cryptomatte (film/cryptomatte.h).
  Film(int width, int height, Rect region, bool halves = false, bool light_passes = false, bool data_passes = false,
       int strategy_max_depth = -1, bool denoising_passes = false, const ShaderAovs &shader_aovs = ShaderAovs(),
       const Cryptomatte &cryptomatte = Cryptomatte());
  // What one pixel costs (samples, splats, AOVs, halves, light and strategy passes): for
  // the memory check before a film is made.
  static size_t bytes_per_pixel(bool halves, bool light_passes = false, int strategy_max_depth = -1,
                                bool denoising_passes = false, int shader_aov_channels = 0, int crypto_slots = 0);
  bool has_halves() const { return !half_splats_.empty(); }
  bool has_light_passes() const { return !light_.empty(); }
  bool writes_data_passes() const { return data_passes_; }
  bool has_denoising_passes() const { return !denoising_.empty(); }
  const ShaderAovs &shader_aovs() const { return shader_aovs_; }
  const Cryptomatte &cryptomatte() const { return cryptomatte_; }
  // Cryptomatte's metadata (crypto_metadata: the layers' names and manifests), for the
  // images the film makes; set by the session from its scene.
  void set_crypto_metadata(nlohmann::json metadata) { crypto_metadata_ = std::move(metadata); }
  const nlohmann::json &crypto_metadata() const { return crypto_metadata_; }
  // Shadow catchers (film/shadow_catcher_passes.h): from now on the film keeps their sums
  // (the path tracer's, BDPT's, pssmlt's and mmlt's in a scene with a catcher), and Combined reads as `display`
  // says. Call before rendering.
  void keep_shadow_catcher(const CatcherDisplay &display);
  bool has_shadow_catcher() const { return !catcher_.empty(); }
  const CatcherDisplay &catcher_display() const { return catcher_display_; }
  const StrategyPasses &strategy_passes() const { return strategies_; }
  int width() const { return width_; }
  int height() const { return height_; }
  const Rect &region() const { return region_; }

  // A render thread's tile: filled with the film's sums of rect, then written back
  // whole. Tiles of one pass must not overlap.
  void take_tile(const Rect &rect, FilmTile &tile) const;
  void put_tile(const FilmTile &tile);

  // A pass's splats and the frame state they make, applied under the frame lock: a
  // read sees both or neither. Splats are applied by one thread in a fixed order
  // (deterministic sums).
  class PassPublisher {
   public:
    explicit PassPublisher(Film &film) : film_(film), lock_(film.frame_mutex_) {}
    // Spreads L over the pixels whose filter covers `raster`, with the same normalised
    // Blackman-Harris weights filter importance sampling gives camera samples, so that
    // splatted and sampled estimates converge to the same image.
    // half_b: the splat belongs to half image B too (film/noise_estimate.h); needs halves.
    // strategy: its strategy pass (film/strategy_passes.h; a t = 1 strategy), or 0xff.
    // light_pass: its light passes (film/light_passes.h), when the film keeps them;
    // shares: its light_pass.shares slot shares, when it has any.
    // catcher: the shadow catcher sums it adds to (BDPT; film/shadow_catcher_passes.h), when
    // the film keeps them (else it is Combined's).
    void add_splat(Vec2 raster, Color L, const PixelFilter &filter, bool half_b = false, uint8_t strategy = 0xff,
                   const SplatLightPass &light_pass = {}, const SlotShare *shares = nullptr,
                   CatcherSplat catcher = CatcherSplat::Combined) {
      film_.add_splat(raster, L, filter, half_b, strategy, light_pass, shares, catcher, film_.region_.y0,
                      film_.region_.y1);
    }
    // Many splats at once, in parallel over bands of rows on the calling task arena:
    // each pixel still gets its splats in the order `each` gives them, so the sums are
    // add_splat's one at a time, bit for bit, on any thread count. (One thread applying a
    // pass's light-tracing splats left the other core idle for 5-15% of a BDPT render.)
    // each(visit) calls visit(raster, L, half_b, strategy, light_pass[, shares[, catcher]]) for every splat.
    template <class EachSplat>
    void add_splats(const PixelFilter &filter, const EachSplat &each) {
      film_.for_each_row_band([&](int y0, int y1) {
        each([&](Vec2 raster, Color L, bool half_b, uint8_t strategy, const SplatLightPass &light_pass,
                 const SlotShare *shares = nullptr, CatcherSplat catcher = CatcherSplat::Combined) {
          film_.add_splat(raster, L, filter, half_b, strategy, light_pass, shares, catcher, y0, y1);
        });
      });
    }
    // The frame now complete: samples (or mutations) per pixel and the splats' scale.
    void publish(uint32_t samples, SplatNormalisation splats) { publish(samples, splats, HalfSplit::None, {}); }
    // The same, with the split into half images that estimates its noise.
    void publish(uint32_t samples, SplatNormalisation splats, HalfSplit split, SplatNormalisation half_splats,
                 double scale_relative_variance = 0) {
      film_.state_ = {film_.state_.pass + 1, samples, splats.scale(), splats, split, half_splats,
                      scale_relative_variance};
    }

   private:
    Film &film_;
    std::lock_guard<std::mutex> lock_;
  };

  FrameState frame_state() const {
    std::lock_guard<std::mutex> frame(frame_mutex_);
    return state_;
  }
  // Rectangle of a pass, row order top-down or bottom-up; state (if given) receives
  // the frame state of what was read.
  void read(rdv_pass pass, int x, int y, int w, int h, bool top_down, float *out, FrameState *state = nullptr) const;

  // The estimated relative MSE of the frame (mean over the rendered region's pixels and
  // channels of the error's variance over (value^2 + 0.01)), from its two half images;
  // infinity while a pixel lacks a sample in either half; negative when the frame has no
  // halves. O(pixels), under the frame lock: once per pass.
  double relative_mse_estimate() const;
  // Adaptive sampling: marks (1) every pixel of the rendered region whose estimated
  // relative error, the root of its relative variance averaged with its 8 neighbours'
  // (27 channel estimates; one pixel's own, from one pair of halves, is too noisy to
  // stop on), is at most `threshold`. Marks stay set. Returns the pixels marked.
  size_t mark_converged(double threshold, std::vector<uint8_t> &converged) const;

  // The raw sums, row-major from the top (writing and merging render parts,
  // film/render_part.h): read them when no render is running.
  std::vector<PixelSum> &pixel_sums() { return pixels_; }
  const std::vector<PixelSum> &pixel_sums() const { return pixels_; }
  std::vector<SplatSums> &splat_sums() { return splats_; }
  const std::vector<SplatSums> &splat_sums() const { return splats_; }
  std::vector<PixelAov> &aov_sums() { return aovs_; }
  const std::vector<PixelAov> &aov_sums() const { return aovs_; }
  // Half image B's sums (empty without halves).
  std::vector<HalfSum> &half_pixel_sums() { return half_pixels_; }
  const std::vector<HalfSum> &half_pixel_sums() const { return half_pixels_; }
  std::vector<SplatSums> &half_splat_sums() { return half_splats_; }
  const std::vector<SplatSums> &half_splat_sums() const { return half_splats_; }
  // Light passes' sums (empty without them).
  std::vector<LightPassSums> &light_pass_sums() { return light_; }
  const std::vector<LightPassSums> &light_pass_sums() const { return light_; }
  std::vector<LightSplatSums> &light_splat_sums() { return light_splats_; }
  const std::vector<LightSplatSums> &light_splat_sums() const { return light_splats_; }
  // Shadow catcher sums (empty without them).
  std::vector<CatcherSums> &shadow_catcher_sums() { return catcher_; }
  const std::vector<CatcherSums> &shadow_catcher_sums() const { return catcher_; }
  // Denoising data's sums (empty without them).
  std::vector<DenoisingSums> &denoising_sums() { return denoising_; }
  const std::vector<DenoisingSums> &denoising_sums() const { return denoising_; }
  // Shader AOVs' sums: shader_aovs().channels per pixel (empty without them); double, as
  // the image's, so render parts add up to the whole render's.
  std::vector<double> &shader_aov_sums() { return shader_aov_sums_; }
  const std::vector<double> &shader_aov_sums() const { return shader_aov_sums_; }
  // Cryptomatte's slots: cryptomatte().slots_per_pixel() per pixel (empty without it).
  std::vector<CryptoSlot> &crypto_slots() { return crypto_; }
  const std::vector<CryptoSlot> &crypto_slots() const { return crypto_; }
  // Strategy passes' sums: strategy_passes().count() per pixel of camera samples and
  // splat_count() of splats (empty without them).
  std::vector<StrategySums> &strategy_sums() { return strategy_; }
  const std::vector<StrategySums> &strategy_sums() const { return strategy_; }
  std::vector<StrategySums> &strategy_splat_sums() { return strategy_splats_; }
  const std::vector<StrategySums> &strategy_splat_sums() const { return strategy_splats_; }

 private:
  // The splat's share in rows [y0, y1) (a band of add_splats).
  void add_splat(Vec2 raster, Color L, const PixelFilter &filter, bool half_b, uint8_t strategy,
                 const SplatLightPass &light_pass, const SlotShare *shares, CatcherSplat catcher, int y0, int y1);
  // Calls band(y0, y1) for disjoint bands of the region's rows that cover it, in parallel.
  void for_each_row_band(const std::function<void(int, int)> &band);
  // One pixel of a shader AOV pass into dst (4 or 1 floats); n: the pixel's sample count.
  void read_shader_aov(rdv_pass pass, size_t i, double n, float *dst) const;
  // One pixel of strategy pass k into dst (3 floats).
  void read_strategy_pass(int k, size_t i, float *dst) const;
  // One pixel of a light pass (RDV_PASS_EMISSION .. RDV_PASS_VOLUME_INDIRECT) into dst.
  void read_light_pass(rdv_pass pass, size_t i, float *dst) const;
  size_t index(int x, int y) const { return size_t(y) * width_ + x; }
  int width_, height_;
  Rect region_;
  std::vector<PixelSum> pixels_;
  std::vector<PixelAov> aovs_;
  std::vector<SplatSums> splats_;
  // Half B's share of pixels_ and splats_; both empty when the film keeps no halves.
  std::vector<HalfSum> half_pixels_;
  std::vector<SplatSums> half_splats_;
  // Light passes: camera samples' sums and splats; both empty unless asked for.
  std::vector<LightPassSums> light_;
  std::vector<LightSplatSums> light_splats_;
  bool data_passes_ = false;
  std::vector<DenoisingSums> denoising_;  // empty unless asked for
  ShaderAovs shader_aovs_;
  std::vector<double> shader_aov_sums_;  // shader_aovs_.channels per pixel
  Cryptomatte cryptomatte_;
  std::vector<CryptoSlot> crypto_;  // cryptomatte_.slots_per_pixel() per pixel
  nlohmann::json crypto_metadata_;
  std::vector<CatcherSums> catcher_;  // empty unless keep_shadow_catcher
  CatcherDisplay catcher_display_;
  // Strategy passes: count() sums per pixel of camera samples, splat_count() of splats;
  // both empty unless asked for.
  StrategyPasses strategies_;
  std::vector<StrategySums> strategy_, strategy_splats_;
  FrameState state_;
  mutable std::mutex frame_mutex_;  // guards all of the above but the sizes
};

}  // namespace rdv
