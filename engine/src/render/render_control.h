// What a session shares with the integrator that renders for it: when to stop (cancel,
// the time limit) and the progress figures the integrator publishes as it goes. Read
// from any thread while rendering; the integrator's hot loops only call should_stop().
#pragma once
#include <atomic>
#include <chrono>
#include <cstdint>

namespace rdv {

class RenderControl {
 public:
  explicit RenderControl(double time_limit) : time_limit_(time_limit) {}

  void start() {
    start_time_ = std::chrono::steady_clock::now();
    running_.store(true);
  }
  // Freezes the elapsed time once the render halted.
  void finish() { final_elapsed_.store(elapsed()); }
  void cancel() { cancel_requested_.store(true); }
  bool cancel_requested() const { return cancel_requested_.load(); }

  bool should_stop() const {
    return cancel_requested_.load(std::memory_order_relaxed) || (time_limit_ > 0 && elapsed() >= time_limit_);
  }
  double elapsed() const {
    double fixed = final_elapsed_.load();
    if (fixed >= 0) return fixed;
    if (!running_.load()) return 0;
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_time_).count();
  }
  double time_limit() const { return time_limit_; }

  // Progress: rays traced and samples dropped (NaN / Inf never enter the film). The
  // samples done are the film's: published with the frame (Film::PassPublisher).
  void add_rays(uint64_t n) { rays_.fetch_add(n, std::memory_order_relaxed); }
  void add_dropped(uint64_t n) { dropped_.fetch_add(n, std::memory_order_relaxed); }
  uint64_t rays() const { return rays_.load(); }
  uint64_t dropped() const { return dropped_.load(); }

 private:
  double time_limit_;
  std::chrono::steady_clock::time_point start_time_;
  std::atomic<bool> cancel_requested_{false}, running_{false};
  std::atomic<double> final_elapsed_{-1.0};
  std::atomic<uint64_t> rays_{0}, dropped_{0};
};

}  // namespace rdv
