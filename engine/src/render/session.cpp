#include "render/session.h"
#include <tbb/task_arena.h>
#include <algorithm>
#include <new>
#include "core/error.h"
#include "core/log.h"

namespace rdv {

Session::Session(std::shared_ptr<Scene> scene, const RenderSettings &settings)
    : scene_(std::move(scene)), settings_(settings),
      film_(settings.width, settings.height, settings.border, settings.estimates_noise(), settings.light_passes,
            settings.data_passes, settings.strategy_pass_depth(), settings.denoising_passes, settings.shader_aovs,
      settings.cryptomatte),
      filter_(settings.filter_width),
      control_(settings.time_limit, settings.noise_target) {
  scene_->commit();
  scene_->camera().set_resolution(settings.width, settings.height);
  if (!settings.cryptomatte.empty())
    film_.set_crypto_metadata(crypto_metadata(settings.cryptomatte, scene_->crypto_manifests()));
  // Shadow catchers (integrators/path/shadow_catcher.h, integrators/bdpt/shadow_catcher.cpp):
  // every integrator splits its paths at them (pssmlt and mmlt through BDPT's samples and
  // strategies, path-space mlt by each path's second contribution, mlt/path_space.h).
  if (scene_->has_shadow_catchers()) {
    film_.keep_shadow_catcher({settings_.shadow_catcher_pass, settings_.alpha.film_transparent});
    if (scene_->has_media())
      scene_->warn(scene_->shadow_catcher_object() + " is a shadow catcher in a scene with participating media: "
                   "its Shadow Catcher pass sees the media of every object (Cycles leaves out those of objects "
                   "that are not shadow catchers)");
  }
  integrator_ = make_integrator(settings_, *scene_);
}

std::string Session::stats_json() const {
  const std::string stats = integrator_->stats_json();
  if (film_.cryptomatte().empty()) return stats;
  nlohmann::json j = nlohmann::json::parse(stats);
  j["cryptomatte"] = film_.crypto_metadata();
  return j.dump();
}

Session::~Session() {
  cancel();
  if (thread_.joinable()) thread_.join();
}

void Session::start() {
  if (running_.exchange(true)) return;
  control_.start();
  thread_ = std::thread([this] { render_loop(); });
}

void Session::wait() {
  if (thread_.joinable()) thread_.join();
  if (finished_.load() && !failure_.empty()) fail(failure_, RDV_ERROR_INTERNAL);
}

void Session::render_loop() {
  // Nothing may leave this thread: an exception here would std::terminate the host
  // (Blender). A failed render halts; wait() reports why, and the film keeps its last frame.
  try {
    tbb::task_arena arena(settings_.threads > 0 ? settings_.threads : tbb::task_arena::automatic);
    RenderContext ctx{*scene_, settings_, film_, filter_, control_, arena};
    integrator_->render(ctx);
  } catch (const std::bad_alloc &) {
    failure_ = "render: out of memory (the image stops at its last complete pass)";
  } catch (const std::exception &e) {
    failure_ = std::string("render: internal error: ") + e.what();
  }
  if (!failure_.empty()) log_warning(failure_);
  control_.finish();
  cancelled_.store(control_.cancel_requested());
  finished_.store(true);
}

Progress Session::progress() const {
  Progress p;
  p.samples_done = film_.frame_state().samples;  // the frame a read shows now
  p.samples_target = settings_.samples;
  p.elapsed = control_.elapsed();
  p.time_limit = control_.time_limit();  // integrator auto may extend it
  p.noise_estimate = control_.noise_estimate();
  p.noise_target = settings_.noise_target;
  p.noise_reached = control_.noise_reached();
  double f = 0;
  if (p.samples_target) f = double(p.samples_done) / p.samples_target;
  if (p.time_limit > 0) f = std::max(f, p.elapsed / p.time_limit);
  // The estimate falls as 1 / samples: target / estimate is the share of the samples done.
  if (p.noise_target > 0 && p.noise_estimate > 0) f = std::max(f, p.noise_target / p.noise_estimate);
  p.finished = finished_.load();
  p.fraction = p.finished ? 1.0 : std::min(f, 1.0);
  p.rays = control_.rays();
  p.rays_per_second = p.elapsed > 0 ? double(p.rays) / p.elapsed : 0;
  p.dropped = control_.dropped();
  p.cancelled = cancelled_.load();
  return p;
}

PartRecord Session::part_record() const {
  PartRecord r;
  r.scene_hash = settings_.scene_hash;
  r.settings_json = settings_.image_settings_json();
  const uint64_t begin = settings_.sample_offset;
  const FrameState frame = film_.frame_state();
  r.ranges.push_back({begin, begin + frame.samples});
  r.splats = frame.splats;
  r.halves = frame.split == HalfSplit::CameraSamples && film_.has_halves();
  if (r.halves) r.half_splats = frame.half_splats;
  r.light_passes = film_.has_light_passes();
  r.data_passes = film_.writes_data_passes();
  r.denoising_passes = film_.has_denoising_passes();
  r.shader_aovs = film_.shader_aovs().to_json();
  r.cryptomatte = film_.cryptomatte().to_json();
  r.crypto_metadata = film_.crypto_metadata();
  r.shadow_catcher = film_.has_shadow_catcher();
  r.catcher_display = film_.catcher_display();
  r.strategy_max_depth = film_.strategy_passes().max_depth;
  return r;
}

}  // namespace rdv
