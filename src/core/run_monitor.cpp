#include "core/run_monitor.hpp"

namespace poreshell {

void RunMonitor::stage(std::string_view name) {
  check();
  std::lock_guard lock(mutex_);
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
