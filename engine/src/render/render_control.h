// What a session shares with the integrator that renders for it: when to stop (cancel,
// the time limit, the noise target) and the progress figures the integrator publishes as it goes. Read
// from any thread while rendering; the integrator's hot loops only call should_stop().
#pragma once
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <limits>

namespace rdv {

class RenderControl {
 public:
  RenderControl(double time_limit, double noise_target) : time_limit_(time_limit), noise_target_(noise_target) {}

  void start() {
    start_time_ = std::chrono::steady_clock::now();
    running_.store(true);
  }
  // Freezes the elapsed time once the render halted.
  void finish() { final_elapsed_.store(elapsed()); }
  void cancel() { cancel_requested_.store(true); }
  bool cancel_requested() const {
    return cancel_requested_.load() || (parent_ && parent_->cancel_requested());
  }
  // A render inside a render (integrator auto's pilots): a cancel of the parent stops it too.
  void follow(const RenderControl &parent) { parent_ = &parent; }
  // Integrator auto, when its pilots overran the share of the limit they were given.
  void extend_time_limit(double seconds) { time_limit_.store(std::max(time_limit_.load(), seconds)); }

  bool should_stop() const {
    return cancel_requested_.load(std::memory_order_relaxed) ||
           (parent_ && parent_->cancel_requested_.load(std::memory_order_relaxed)) ||
           noise_reached_.load(std::memory_order_relaxed) || time_is_up();
  }
  // The published frame's estimated relative MSE (film/noise_estimate.h): below the
  // noise target, the render halts. Integrators report it after each pass they publish.
  void report_noise_estimate(double estimate) {
    noise_estimate_.store(estimate);
    if (noise_target_ > 0 && estimate >= 0 && estimate < noise_target_) noise_reached_.store(true);
  }
  double noise_estimate() const { return noise_estimate_.load(); }
  double noise_target() const { return noise_target_; }
  bool noise_reached() const { return noise_reached_.load(); }
  double elapsed() const {
    double fixed = final_elapsed_.load();
    if (fixed >= 0) return fixed;
    if (!running_.load()) return 0;
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_time_).count();
  }
  double time_limit() const { return time_limit_.load(); }

  // Progress: rays traced and samples dropped (NaN / Inf never enter the film). The
  // samples done are the film's: published with the frame (Film::PassPublisher).
  void add_rays(uint64_t n) { rays_.fetch_add(n, std::memory_order_relaxed); }
  void add_dropped(uint64_t n) { dropped_.fetch_add(n, std::memory_order_relaxed); }
  uint64_t rays() const { return rays_.load(); }
  uint64_t dropped() const { return dropped_.load(); }

 private:
  bool time_is_up() const {
    const double limit = time_limit_.load(std::memory_order_relaxed);
    return limit > 0 && elapsed() >= limit;
  }
  std::atomic<double> time_limit_;
  double noise_target_;
  const RenderControl *parent_ = nullptr;
  std::atomic<double> noise_estimate_{-1.0};
  std::atomic<bool> noise_reached_{false};
  std::chrono::steady_clock::time_point start_time_;
  std::atomic<bool> cancel_requested_{false}, running_{false};
  std::atomic<double> final_elapsed_{-1.0};
  std::atomic<uint64_t> rays_{0}, dropped_{0};
};

}  // namespace rdv
