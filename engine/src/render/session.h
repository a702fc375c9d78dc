// A render session: progressive passes over the whole image on all cores (oneTBB),
// in the engine's own thread. Halts on a sample count or a time limit (always one of
// them), stops within ~100 ms of cancel(), and reports progress at any time.
#pragma once
#include <atomic>
#include <chrono>
#include <memory>
#include <mutex>
#include <thread>
#include "film/film.h"
#include "film/pixel_filter.h"
#include "integrators/integrator.h"

namespace rdv {

struct Progress {
  uint32_t samples_done = 0, samples_target = 0;
  double elapsed = 0, time_limit = 0, fraction = 0, rays_per_second = 0;
  uint64_t rays = 0, dropped = 0;
  bool finished = false, cancelled = false;
};

class Session {
 public:
  Session(std::shared_ptr<Scene> scene, const RenderSettings &settings);
  ~Session();
  void start();
  void wait();
  void cancel() { cancel_requested_.store(true); }
  Progress progress() const;
  const Film &film() const { return film_; }
  const RenderSettings &settings() const { return settings_; }

  // Renders samples [first, last) of every pixel of one tile; used by the render
  // loop and by tests that need a single deterministic pass.
  void render_tile(size_t tile_index, uint32_t first, uint32_t last);

 private:
  void render_loop();
  bool should_stop() const;
  double elapsed() const;

  std::shared_ptr<Scene> scene_;
  RenderSettings settings_;
  Film film_;
  PixelFilter filter_;
  std::unique_ptr<Integrator> integrator_;
  std::vector<Rect> tiles_;
  std::vector<std::vector<Splat>> tile_splats_;  // per tile, applied in tile order after a pass

  std::thread thread_;
  std::atomic<bool> cancel_requested_{false}, running_{false}, finished_{false}, cancelled_{false};
  std::atomic<uint32_t> samples_done_{0};
  std::atomic<uint64_t> rays_{0}, dropped_{0};
  std::chrono::steady_clock::time_point start_time_;
  std::atomic<double> final_elapsed_{-1.0};
};

}  // namespace rdv
