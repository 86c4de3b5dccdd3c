#pragma once
// A run's progress reports and cancellation, handed to the stages that take long. Any thread may call
// it: the callback is serialised and rate-limited, and check() throws Cancelled once the caller's flag
// is set, OutOfTime once the run is past its time budget (from a oneTBB worker, the exception cancels
// the parallel loop and reaches the run's caller).

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <mutex>
#include <stop_token>
#include <string>
#include <string_view>
#include <thread>

#include "core/error.hpp"
#include "poreshell/progress.hpp"

namespace poreshell {

class RunMonitor {
 public:
  RunMonitor() = default;
  // With control.max_seconds > 0, a watchdog thread raises the out-of-time flag at the deadline (so
  // that check() stays one load, not a clock read).
  explicit RunMonitor(const RunControl& control);
  ~RunMonitor();
  RunMonitor(const RunMonitor&) = delete;
  RunMonitor& operator=(const RunMonitor&) = delete;

  // A new stage: reports (stage, 0) at once.
  void stage(std::string_view name);
  // Progress within the current stage; reported at most every kInterval unless `force`. Checks the
  // cancel flag first. `step`: the solve's time step (0 elsewhere). The fraction reported never goes
  // back within a stage. Cheap when not reporting (one clock read), so loops may call it often.
  void advance(double fraction, std::string_view message = {}, int step = 0, bool force = false);
  // Throws Cancelled when the caller's flag is set, OutOfTime past the budget. Cheap: two relaxed loads.
  void check() const {
    if (control_.cancel && control_.cancel->load(std::memory_order_relaxed)) throw Cancelled();
    if (out_of_time_.load(std::memory_order_relaxed)) throw_out_of_time();
  }
  // Whether the run must stop, for code that must stop by itself rather than by an exception.
  bool cancelled() const {
    return (control_.cancel && control_.cancel->load(std::memory_order_relaxed)) ||
           out_of_time_.load(std::memory_order_relaxed);
  }
  double seconds() const;

 private:
  static constexpr std::chrono::milliseconds kInterval{200};
  [[noreturn]] void throw_out_of_time() const;

  RunControl control_;
  std::atomic<bool> out_of_time_{false};
  mutable std::mutex mutex_;  // for the callback and stage_
  std::string stage_;
  double fraction_ = 0.0;  // the last reported in this stage
  const std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
  std::atomic<std::int64_t> last_{0};  // the last report, steady_clock ticks since start_
  std::jthread watchdog_;              // last: stopped and joined before the rest goes
};

// A share [begin, end] of the current stage's progress, handed to a function that does part of a stage
// (in its options struct): its fractions 0..1 map onto that share. Copyable; default: no monitor, so
// tests and benchmarks call the stages as before. check() and advance() may be called from oneTBB
// workers: a Cancelled thrown there cancels the parallel loop and reaches the caller, and the stage's
// partial results go with the stack that unwinds.
class StageProgress {
 public:
  StageProgress() = default;
  explicit StageProgress(RunMonitor& monitor, double begin = 0.0, double end = 1.0)
      : monitor_(&monitor), begin_(begin), end_(end) {}

  void check() const {
    if (monitor_) monitor_->check();
  }
  bool cancelled() const { return monitor_ && monitor_->cancelled(); }
  // `fraction` of this share done: checks the flag, reports if the last report is old enough.
  void advance(double fraction) const {
    if (monitor_) monitor_->advance(begin_ + std::clamp(fraction, 0.0, 1.0) * (end_ - begin_));
  }
  // The sub-share [from, to] of this share (fractions of it).
  StageProgress part(double from, double to) const {
    StageProgress p = *this;
    p.begin_ = begin_ + from * (end_ - begin_);
    p.end_ = begin_ + to * (end_ - begin_);
    return p;
  }

 private:
  RunMonitor* monitor_ = nullptr;
  double begin_ = 0.0, end_ = 1.0;
};

// Progress of a loop of `total` items, any thread: done(n) after n more items checks the flag and
// reports the share done now and then.
class LoopProgress {
 public:
  LoopProgress(const StageProgress& progress, std::size_t total) : progress_(progress), total_(total) {}
  void done(std::size_t items = 1) {
    progress_.check();
    const std::size_t now = done_.fetch_add(items, std::memory_order_relaxed) + items;
    if (total_ > 0) progress_.advance(static_cast<double>(now) / static_cast<double>(total_));
  }

 private:
  StageProgress progress_;
  std::size_t total_;
  std::atomic<std::size_t> done_{0};
};

// Monitor used where a stage is called without one (tests, benchmarks).
RunMonitor& unmonitored();

}  // namespace poreshell
