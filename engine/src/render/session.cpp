#include "render/session.h"
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

namespace rdv {

static constexpr int kTileSize = 16;

Session::Session(std::shared_ptr<Scene> scene, const RenderSettings &settings)
    : scene_(std::move(scene)), settings_(settings),
      film_(settings.width, settings.height, settings.border), filter_(settings.filter_width) {
  scene_->commit();
  scene_->camera().set_resolution(settings.width, settings.height);
  integrator_ = make_integrator(settings_, *scene_);
  const Rect &r = settings_.border;
  for (int y = r.y0; y < r.y1; y += kTileSize)
    for (int x = r.x0; x < r.x1; x += kTileSize)
      tiles_.push_back({x, y, std::min(x + kTileSize, r.x1), std::min(y + kTileSize, r.y1)});
  tile_splats_.resize(tiles_.size());
}

Session::~Session() {
  cancel();
  if (thread_.joinable()) thread_.join();
}

void Session::start() {
  if (running_.exchange(true)) return;
  start_time_ = std::chrono::steady_clock::now();
  thread_ = std::thread([this] { render_loop(); });
}

void Session::wait() {
  if (thread_.joinable()) thread_.join();
}

double Session::elapsed() const {
  double fixed = final_elapsed_.load();
  if (fixed >= 0) return fixed;
  if (!running_.load()) return 0;
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_time_).count();
}

bool Session::should_stop() const {
  return cancel_requested_.load(std::memory_order_relaxed) ||
         (settings_.time_limit > 0 && elapsed() >= settings_.time_limit);
}

void Session::render_tile(size_t tile_index, uint32_t first, uint32_t last) {
  const Rect &tile = tiles_[tile_index];
  std::vector<Splat> &splats = tile_splats_[tile_index];
  splats.clear();
  SobolSampler sobol(settings_.seed);
  IndependentSampler independent(settings_.seed);
  Sampler &sampler = settings_.sampler == "sobol" ? static_cast<Sampler &>(sobol) : independent;
  RayStats stats;
  uint64_t dropped = 0;
  const Camera &camera = scene_->camera();
  for (int y = tile.y0; y < tile.y1; ++y) {
    for (int x = tile.x0; x < tile.x1; ++x) {
      if (should_stop()) goto done;  // cancel latency: one pixel's batch of samples
      for (uint32_t s = first; s < last; ++s) {
        sampler.start_sample(uint32_t(x), uint32_t(y), s);
        Vec2 uf = sampler.get_2d();
        Vec2 raster{x + 0.5f + filter_.sample(uf.x), y + 0.5f + filter_.sample(uf.y)};
        CameraRay cr;
        cr.ray = camera.generate_ray(raster, sampler.get_2d(), &cr.lens_point, &cr.cone);
        FirstHit first_hit;
        Color L = integrator_->Li(cr, sampler, stats, &first_hit, splats);
        if (!is_finite(L) || L.x < 0 || L.y < 0 || L.z < 0) {  // never let NaN/Inf into the film
          ++dropped;
          continue;
        }
        if (settings_.clamp > 0) {
          float m = max_component(L);
          if (m > settings_.clamp) L *= settings_.clamp / m;
        }
        film_.add_sample(x, y, L);
        if (first_hit.valid) film_.add_first_hit(x, y, first_hit.depth, first_hit.normal, first_hit.albedo);
        else film_.add_first_hit(x, y, 1e10f, Vec3(0.0f), Color(0.0f));
      }
    }
  }
done:
  rays_.fetch_add(stats.rays, std::memory_order_relaxed);
  dropped_.fetch_add(dropped, std::memory_order_relaxed);
}

void Session::render_loop() {
  tbb::task_arena arena(settings_.threads > 0 ? settings_.threads : tbb::task_arena::automatic);
  uint32_t batch = 1;
  uint32_t done = 0;
  const uint32_t target = settings_.samples;  // 0: until the time limit
  while (!should_stop() && (target == 0 || done < target)) {
    uint32_t last = target ? std::min(target, done + batch) : done + batch;
    auto pass_start = std::chrono::steady_clock::now();
    arena.execute([&] {
      tbb::parallel_for(tbb::blocked_range<size_t>(0, tiles_.size(), 1), [&](const tbb::blocked_range<size_t> &r) {
        for (size_t i = r.begin(); i != r.end(); ++i) render_tile(i, done, last);
      });
    });
    if (should_stop()) break;  // an interrupted pass does not count, nor do its splats
    for (auto &splats : tile_splats_)  // in tile order: the same sums on any thread count
      for (const Splat &sp : splats) film_.add_splat(sp.raster, sp.L, filter_);
    done = last;
    samples_done_.store(done);
    // One light path per camera sample, over the rendered region only; the camera's
    // importance is normalised over the whole image.
    const Rect &b = settings_.border;
    film_.set_splat_scale(float(settings_.width) * settings_.height / (float(b.width()) * b.height() * done));
    // Grow the batch while passes are short, so progress updates stay ~4 per second.
    double pass_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - pass_start).count();
    if (pass_seconds < 0.125 && batch < 64) batch *= 2;
  }
  final_elapsed_.store(elapsed());
  cancelled_.store(cancel_requested_.load());
  finished_.store(true);
}

Progress Session::progress() const {
  Progress p;
  p.samples_done = samples_done_.load();
  p.samples_target = settings_.samples;
  p.elapsed = elapsed();
  p.time_limit = settings_.time_limit;
  double f = 0;
  if (p.samples_target) f = double(p.samples_done) / p.samples_target;
  if (p.time_limit > 0) f = std::max(f, p.elapsed / p.time_limit);
  p.finished = finished_.load();
  p.fraction = p.finished ? 1.0 : std::min(f, 1.0);
  p.rays = rays_.load();
  p.rays_per_second = p.elapsed > 0 ? double(p.rays) / p.elapsed : 0;
  p.dropped = dropped_.load();
  p.cancelled = cancelled_.load();
  return p;
}

}  // namespace rdv
