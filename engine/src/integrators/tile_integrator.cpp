#include "integrators/tile_integrator.h"
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <algorithm>
#include <chrono>
#include <cmath>
#include "core/limits.h"
#include "samplers/dimension_layout.h"

namespace rdv {

static constexpr int kTileSize = 16;

void TileIntegrator::render_tile(RenderContext &ctx, const Rect &tile, uint32_t first, uint32_t last,
                                 const std::vector<uint8_t> &converged, TileSplats &splats) const {
  const RenderSettings &settings = ctx.settings;
  splats.a.clear();
  splats.b.clear();
  const bool light_passes = ctx.film.has_light_passes();
  const bool denoising_passes = ctx.film.has_denoising_passes();
  LightPassSample passes;
  // Shadow catchers (film/shadow_catcher_passes.h): the sample's matte, catcher pass, split.
  const bool shadow_catcher = ctx.film.has_shadow_catcher();
  CatcherSample catcher;
  // Strategy passes (film/strategy_passes.h): the sample's share in each.
  const StrategyPasses &strategy_layout = ctx.film.strategy_passes();
  thread_local std::vector<Color> strategies;
  strategies.assign(size_t(strategy_layout.count()), Color(0.0f));
  splats.paths = splats.half_b_paths = 0;
  // Estimating the noise, samples alternate between two independently scrambled
  // replicates of the sequence, half images A and B (film/noise_estimate.h): the even
  // and odd samples of one Owen-scrambled sequence are not independent (each half is
  // stratified against the other), and their difference would overstate the error of
  // the whole by the sequence's gain, 2-3x on the Cornell box at 64 samples.
  const bool replicates = settings.estimates_noise();
  const uint32_t seed_b = hash_combine(settings.seed, 0x72657062u);
  SobolSampler sobol(settings.seed), sobol_b(seed_b);
  IndependentSampler independent(settings.seed), independent_b(seed_b);
  const bool use_sobol = settings.sampler == "sobol";
  Sampler &sampler_a = use_sobol ? static_cast<Sampler &>(sobol) : independent;
  Sampler &sampler_b = use_sobol ? static_cast<Sampler &>(sobol_b) : independent_b;
  RayStats stats;
  uint64_t dropped = 0;
  const bool motion = ctx.scene.has_motion();
  thread_local FilmTile film_tile;  // this thread's pixels of the tile, published whole
  ctx.film.take_tile(tile, film_tile);
  for (int y = tile.y0; y < tile.y1; ++y) {
    for (int x = tile.x0; x < tile.x1; ++x) {
      if (ctx.control.should_stop()) goto done;
      if (!converged.empty() && converged[size_t(y) * size_t(ctx.film.width()) + size_t(x)]) continue;
      splats.paths += last - first;
      for (uint32_t s = first; s < last; ++s) {
        const bool half_b = replicates && (s & 1);
        splats.half_b_paths += half_b;
        Sampler &sampler = half_b ? sampler_b : sampler_a;
        sampler.start_sample(uint32_t(x), uint32_t(y), replicates ? s >> 1 : s);
        Vec2 uf = sampler.get_2d();
        Vec2 raster{x + 0.5f + ctx.filter.sample(uf.x), y + 0.5f + ctx.filter.sample(uf.y)};
        Vec2 u_lens = sampler.get_2d();
        // Motion blur: the whole sample, both subpaths, is traced at one shutter time.
        shutter::SampleTime at(motion ? dims::shutter_time(sampler) : shutter::now());
        CameraRay cr;
        cr.ray = ctx.scene.camera_now().generate_ray(raster, u_lens, &cr.lens_point, &cr.cone);
        FirstHit first_hit;
        first_hit.data.denoising.active = denoising_passes;
        first_hit.data.aovs.start(&ctx.film.shader_aovs());
        first_hit.data.crypto.start(&ctx.film.cryptomatte());
        if (light_passes) {
          passes.clear();
          first_hit.passes = &passes;
        }
        if (shadow_catcher) {
          catcher = CatcherSample{};
          first_hit.catcher = &catcher;
        }
        if (strategy_layout.enabled()) {
          std::fill(strategies.begin(), strategies.end(), Color(0.0f));
          first_hit.strategy_layout = strategy_layout;
          first_hit.strategies = strategies.data();
        }
        Color L = Li(cr, sampler, stats, &first_hit, half_b ? splats.b : splats.a);
        if (!is_finite(L) || L.x < 0 || L.y < 0 || L.z < 0 || (shadow_catcher && !catcher.valid())) {
          ++dropped;  // never let NaN/Inf into the film
          continue;
        }
        if (settings.clamp > 0) {
          float m = max_component(L);
          if (m > settings.clamp) {
            L *= settings.clamp / m;
            if (light_passes) passes.scale(settings.clamp / m);
            for (Color &c : strategies) c *= settings.clamp / m;
            catcher.matte *= settings.clamp / m;  // a part of L: scaled with it
          }
          if (shadow_catcher)  // the catcher pass's path and the world behind: as a Combined of their own
            for (Color *c : {&catcher.catcher, &catcher.background})
              if (max_component(*c) > settings.clamp) *c *= settings.clamp / max_component(*c);
        }
        film_tile.add_sample(x, y, L, half_b, first_hit.transparency);
        film_tile.add_data_passes(x, y, first_hit.data, s == 0);
        if (light_passes) film_tile.add_light_passes(x, y, passes);
        if (shadow_catcher) film_tile.add_shadow_catcher(x, y, catcher);
        if (strategy_layout.enabled()) film_tile.add_strategy_passes(x, y, strategies.data());
        if (first_hit.valid) film_tile.add_first_hit(x, y, first_hit.depth, first_hit.normal, first_hit.albedo);
        else film_tile.add_first_hit(x, y, 1e10f, Vec3(0.0f), Color(0.0f));
      }
    }
  }
done:
  ctx.film.put_tile(film_tile);  // an interrupted tile's samples are whole samples too
  ctx.control.add_rays(stats.rays);
  ctx.control.add_dropped(dropped);
}

std::vector<Rect> TileIntegrator::tiles(const Rect &r) {
  std::vector<Rect> tiles;
  for (int y = r.y0; y < r.y1; y += kTileSize)
    for (int x = r.x0; x < r.x1; x += kTileSize)
      tiles.push_back({x, y, std::min(x + kTileSize, r.x1), std::min(y + kTileSize, r.y1)});
  return tiles;
}

void TileIntegrator::render(RenderContext &ctx) {
  const Rect &r = ctx.settings.border;
  const std::vector<Rect> tiles = TileIntegrator::tiles(r);
  std::vector<TileSplats> tile_splats(tiles.size());  // applied in tile order after a pass
  uint64_t paths = 0, half_b_paths = 0;  // light paths traced (by half B's samples), all passes
  // Adaptive sampling: pixels that stopped, checked at fixed sample counts (the same
  // image on any thread count and machine).
  std::vector<uint8_t> converged;
  const bool adaptive = ctx.settings.adaptive_sampling;
  uint32_t next_check = adaptive ? ctx.settings.adaptive_first_check() : UINT32_MAX;
  const size_t region_pixels = size_t(r.width()) * size_t(r.height());

  uint32_t batch = 1;
  uint32_t done = 0;
  // 0: until the time limit, or the film's exact sample count (kMaxSamplesPerPixel).
  const uint32_t target = ctx.settings.samples ? ctx.settings.samples : kMaxSamplesPerPixel;
  // A part of a render (a farm task) renders samples [offset, offset + samples) of the
  // whole render's sequence: the same camera samples and, since each camera sample
  // traces its own light path (BDPT), the same light paths.
  const uint32_t offset = ctx.settings.sample_offset;
  while (!ctx.control.should_stop() && done < target) {
    uint32_t last = std::min(target, done + batch);
    last = std::min<uint64_t>(last, uint64_t(UINT32_MAX) - offset);  // sample indices stay 32-bit
    if (adaptive && done < next_check) last = std::min(last, next_check);
    if (last <= done) break;
    auto pass_start = std::chrono::steady_clock::now();
    ctx.arena.execute([&] {
      tbb::parallel_for(tbb::blocked_range<size_t>(0, tiles.size(), 1), [&](const tbb::blocked_range<size_t> &b) {
        for (size_t i = b.begin(); i != b.end(); ++i) render_tile(ctx, tiles[i], offset + done, offset + last, converged, tile_splats[i]);
      });
    });
    if (ctx.control.should_stop()) break;  // an interrupted pass does not count, nor do its splats
    done = last;
    {
      Film::PassPublisher frame(ctx.film);
      ctx.arena.execute([&] {
        frame.add_splats(ctx.filter, [&](const auto &visit) {  // in tile order: the same sums on any thread count
          for (const TileSplats &splats : tile_splats) {
            for (const Splat &sp : splats.a) visit(sp.raster, sp.L, false, sp.strategy, sp.light_pass, nullptr, sp.catcher);
            for (const Splat &sp : splats.b) visit(sp.raster, sp.L, true, sp.strategy, sp.light_pass, nullptr, sp.catcher);
          }
        });
      });
      for (const TileSplats &splats : tile_splats) {
        paths += splats.paths;
        half_b_paths += splats.half_b_paths;
      }
      // One light path per camera sample, over the rendered region only (fewer where
      // adaptive sampling stopped pixels); the camera's importance is normalised over
      // the whole image.
      const double numerator = double(ctx.settings.width) * double(ctx.settings.height);
      frame.publish(done, {numerator, double(paths)},
                    ctx.settings.estimates_noise() ? HalfSplit::CameraSamples : HalfSplit::None,
                    {numerator, double(half_b_paths)});
    }
    // Grow the batch while passes are short, so progress updates stay ~4 per second;
    // estimating the noise, by a fixed schedule instead: where a render halts (noise
    // target) must not depend on the machine's speed.
    double pass_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - pass_start).count();
    if (ctx.settings.estimates_noise() ? batch < 16 : pass_seconds < 0.125 && batch < 64) batch *= 2;
    if (adaptive && done >= next_check) {
      const size_t marked = ctx.film.mark_converged(ctx.settings.adaptive_threshold, converged);
      next_check = done + std::max(4u, done / 8);
      if (marked == region_pixels) break;  // every pixel converged
    }
    if (ctx.settings.estimates_noise()) {
      const double estimate = ctx.film.relative_mse_estimate();
      ctx.control.report_noise_estimate(estimate);
      // The estimate falls as 1 / samples: do not overshoot the target by more than the
      // samples it takes to get there.
      if (ctx.settings.noise_target > 0 && std::isfinite(estimate) && estimate > ctx.settings.noise_target) {
        double needed = std::ceil(double(done) * (estimate / ctx.settings.noise_target - 1.0));
        batch = uint32_t(std::clamp(needed, 1.0, double(batch)));
      }
    }
  }
}

}  // namespace rdv
