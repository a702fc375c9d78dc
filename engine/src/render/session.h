// A render session: runs the integrator's render loop in the engine's own thread on a
// oneTBB arena of the requested size. The integrator renders (tile passes, MLT chains);
// the session schedules, halts (sample count, time limit, cancel: always one of them;
// stops within ~100 ms of cancel(); the noise target) and publishes progress and the frame at any time.
#pragma once
#include <atomic>
#include <memory>
#include <string>
#include <thread>
#include "film/film.h"
#include "film/pixel_filter.h"
#include "film/render_part.h"
#include "integrators/integrator.h"
#include "render/render_control.h"

namespace rdv {

struct Progress {
  uint32_t samples_done = 0, samples_target = 0;
  double elapsed = 0, time_limit = 0, fraction = 0, rays_per_second = 0;
  uint64_t rays = 0, dropped = 0;
  double noise_estimate = -1, noise_target = 0;  // estimated relative MSE (-1: not estimated)
  bool finished = false, cancelled = false, noise_reached = false;
};

class Session {
 public:
  Session(std::shared_ptr<Scene> scene, const RenderSettings &settings);
  ~Session();
  void start();
  // Blocks until the render halts; throws if the render thread failed (out of memory).
  void wait();
  void cancel() { control_.cancel(); }
  Progress progress() const;
  // The integrator's own figures (JSON object; MLT: acceptance, chains, b).
  std::string integrator_stats() const { return integrator_->stats_json(); }
  // Those, and the Cryptomatte layers' metadata ("cryptomatte", when the film keeps it).
  std::string stats_json() const;
  const Film &film() const { return film_; }
  // What a render part written now holds: samples [offset, offset + samples done).
  PartRecord part_record() const;
  const RenderSettings &settings() const { return settings_; }

 private:
  void render_loop();

  std::shared_ptr<Scene> scene_;
  RenderSettings settings_;
  Film film_;
  PixelFilter filter_;
  std::unique_ptr<Integrator> integrator_;
  RenderControl control_;

  std::thread thread_;
  std::atomic<bool> running_{false}, finished_{false}, cancelled_{false};
  std::string failure_;  // why the render thread stopped early (written before finished_)
};

}  // namespace rdv
