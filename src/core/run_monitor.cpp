#include "core/run_monitor.hpp"

#include <fmt/core.h>

namespace poreshell {

RunMonitor::RunMonitor(const RunControl& control) : control_(control) {
  if (!(control_.max_seconds > 0.0)) return;
  const auto deadline = start_ + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                     std::chrono::duration<double>(control_.max_seconds));
  watchdog_ = std::jthread([this, deadline](std::stop_token stop) {
    std::mutex m;
    std::condition_variable_any woken;
    std::unique_lock lock(m);
    // Returns early only when the run ends (the destructor's stop request).
    if (!woken.wait_until(lock, stop, deadline, [] { return false; }))
      if (!stop.stop_requested()) out_of_time_.store(true, std::memory_order_relaxed);
  });
}

RunMonitor::~RunMonitor() = default;

void RunMonitor::throw_out_of_time() const {
  std::string stage;
  {
    std::lock_guard lock(mutex_);
    stage = stage_;
  }
  throw Error(ErrorCode::out_of_time,
              fmt::format("the run passed its time budget of {:g} s (`max_seconds`) in stage '{}'; nothing "
                          "was written; allow more time, or ask for larger holes or a coarser `voxel_size`",
                          control_.max_seconds, stage));
}

void RunMonitor::stage(std::string_view name) {
  check();
  std::lock_guard lock(mutex_);
  if (name == stage_) return;  // already in it (a run that prepared its input in this stage)
  stage_ = name;
  fraction_ = 0.0;
  last_.store((std::chrono::steady_clock::now() - start_).count(), std::memory_order_relaxed);
  if (control_.progress) control_.progress(Progress{stage_, 0.0, {}, 0, seconds()});
}

void RunMonitor::advance(double fraction, std::string_view message, int step, bool force) {
  check();
  if (!control_.progress) return;
  const std::int64_t now = (std::chrono::steady_clock::now() - start_).count();
  const std::int64_t interval = std::chrono::steady_clock::duration(kInterval).count();
  // A first look without the lock: loops on many threads call this often.
  if (!force && now - last_.load(std::memory_order_relaxed) < interval) return;
  std::lock_guard lock(mutex_);
  if (!force && now - last_.load(std::memory_order_relaxed) < interval) return;
  last_.store(now, std::memory_order_relaxed);
  fraction_ = std::max(fraction_, fraction);
  control_.progress(Progress{stage_, fraction_, message, step, seconds()});
}

double RunMonitor::seconds() const {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
}

RunMonitor& unmonitored() {
  // No callback, no flag: its state is only the rate limiter, harmless to share.
  static RunMonitor monitor;
  return monitor;
}

}  // namespace poreshell
