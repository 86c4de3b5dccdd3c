#include "core/run_monitor.hpp"

namespace poreshell {

void RunMonitor::stage(std::string_view name) {
  check();
  std::lock_guard lock(mutex_);
  stage_ = name;
  last_ = std::chrono::steady_clock::now();
  if (control_.progress) control_.progress(Progress{stage_, 0.0, {}, 0, seconds()});
}

void RunMonitor::advance(double fraction, std::string_view message, int step, bool force) {
  check();
  if (!control_.progress) return;
  const auto now = std::chrono::steady_clock::now();
  std::lock_guard lock(mutex_);
  if (!force && now - last_ < kInterval) return;
  last_ = now;
  control_.progress(Progress{stage_, fraction, message, step, seconds()});
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
