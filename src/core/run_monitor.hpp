#pragma once
// A run's progress reports and cancellation, handed to the stages that take long. Any thread may call
// it: the callback is serialised and rate-limited, and check() throws Cancelled once the caller's flag
// is set (from a oneTBB worker, the exception cancels the parallel loop and reaches the run's caller).

#include <atomic>
#include <chrono>
#include <mutex>
#include <string>
#include <string_view>

#include "core/error.hpp"
#include "poreshell/progress.hpp"

namespace poreshell {

class RunMonitor {
 public:
  RunMonitor() = default;
  explicit RunMonitor(const RunControl& control) : control_(control) {}

  // A new stage: reports (stage, 0) at once.
  void stage(std::string_view name);
  // Progress within the current stage; reported at most every kInterval unless `force`. Checks the
  // cancel flag first. `step`: the solve's time step (0 elsewhere).
  void advance(double fraction, std::string_view message = {}, int step = 0, bool force = false);
  // Throws Cancelled when the caller's flag is set. Cheap: one relaxed load.
  void check() const {
    if (control_.cancel && control_.cancel->load(std::memory_order_relaxed)) throw Cancelled();
  }
  double seconds() const;

 private:
  static constexpr std::chrono::milliseconds kInterval{200};
  RunControl control_;
  std::mutex mutex_;
  std::string stage_;
  const std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
  std::chrono::steady_clock::time_point last_{};
};

// Monitor used where a stage is called without one (tests, benchmarks).
RunMonitor& unmonitored();

}  // namespace poreshell
