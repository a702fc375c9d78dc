#include "integrators/tile_integrator.h"
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <chrono>
#include "core/limits.h"

namespace rdv {

static constexpr int kTileSize = 16;

void TileIntegrator::render_tile(RenderContext &ctx, const Rect &tile, uint32_t first, uint32_t last,
                                 std::vector<Splat> &splats) const {
  const RenderSettings &settings = ctx.settings;
  splats.clear();
  SobolSampler sobol(settings.seed);
  IndependentSampler independent(settings.seed);
  Sampler &sampler = settings.sampler == "sobol" ? static_cast<Sampler &>(sobol) : independent;
  RayStats stats;
  uint64_t dropped = 0;
  const Camera &camera = ctx.scene.camera();
  thread_local FilmTile film_tile;  // this thread's pixels of the tile, published whole
  ctx.film.take_tile(tile, film_tile);
  for (int y = tile.y0; y < tile.y1; ++y) {
    for (int x = tile.x0; x < tile.x1; ++x) {
      if (ctx.control.should_stop()) goto done;
      for (uint32_t s = first; s < last; ++s) {
        sampler.start_sample(uint32_t(x), uint32_t(y), s);
        Vec2 uf = sampler.get_2d();
        Vec2 raster{x + 0.5f + ctx.filter.sample(uf.x), y + 0.5f + ctx.filter.sample(uf.y)};
        CameraRay cr;
        cr.ray = camera.generate_ray(raster, sampler.get_2d(), &cr.lens_point, &cr.cone);
        FirstHit first_hit;
        Color L = Li(cr, sampler, stats, &first_hit, splats);
        if (!is_finite(L) || L.x < 0 || L.y < 0 || L.z < 0) {  // never let NaN/Inf into the film
          ++dropped;
          continue;
        }
        if (settings.clamp > 0) {
          float m = max_component(L);
          if (m > settings.clamp) L *= settings.clamp / m;
        }
        film_tile.add_sample(x, y, L);
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

void TileIntegrator::render(RenderContext &ctx) {
  const Rect &r = ctx.settings.border;
  std::vector<Rect> tiles;
  for (int y = r.y0; y < r.y1; y += kTileSize)
    for (int x = r.x0; x < r.x1; x += kTileSize)
      tiles.push_back({x, y, std::min(x + kTileSize, r.x1), std::min(y + kTileSize, r.y1)});
  std::vector<std::vector<Splat>> tile_splats(tiles.size());  // applied in tile order after a pass

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
    if (last <= done) break;
    auto pass_start = std::chrono::steady_clock::now();
    ctx.arena.execute([&] {
      tbb::parallel_for(tbb::blocked_range<size_t>(0, tiles.size(), 1), [&](const tbb::blocked_range<size_t> &b) {
        for (size_t i = b.begin(); i != b.end(); ++i) render_tile(ctx, tiles[i], offset + done, offset + last, tile_splats[i]);
      });
    });
    if (ctx.control.should_stop()) break;  // an interrupted pass does not count, nor do its splats
    done = last;
    {
      Film::PassPublisher frame(ctx.film);
      for (auto &splats : tile_splats)  // in tile order: the same sums on any thread count
        for (const Splat &sp : splats) frame.add_splat(sp.raster, sp.L, ctx.filter);
      // One light path per camera sample, over the rendered region only; the camera's
      // importance is normalised over the whole image.
      frame.publish(done, {double(ctx.settings.width) * double(ctx.settings.height),
                           double(r.width()) * double(r.height()) * double(done)});
    }
    // Grow the batch while passes are short, so progress updates stay ~4 per second.
    double pass_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - pass_start).count();
    if (pass_seconds < 0.125 && batch < 64) batch *= 2;
  }
}

}  // namespace rdv
