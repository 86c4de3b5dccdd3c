#pragma once
// Progress and cancellation of a run.

#include <atomic>
#include <functional>
#include <string_view>

namespace poreshell {

// `stage` and `message` view the run's own strings and are valid only during the callback: a caller
// that keeps them copies them (std::string(p.stage)).
struct Progress {
  std::string_view stage;    // input, band, solve, shell, mesh, holes
  double fraction = 0.0;     // of this stage, 0..1 (the solve's: from the stopping rule's progress)
  std::string_view message;  // a line for people (the solve: step, e_c, inner iterations)
  int step = 0;              // the solve: the time step just taken (0 elsewhere)
  double seconds = 0.0;      // since the run started
};

// The callback is called from the run's threads, one call at a time, at least at every stage's start
// and end and a few times a second in long stages. Throwing from it cancels the run: the exception
// reaches perforate()'s caller. Setting *cancel stops the run within about half a second with
// Error(cancelled). A run past `max_seconds` (0: no budget) stops as soon with Error(out_of_time).
// Nothing is ever written by a run.
struct RunControl {
  std::function<void(const Progress&)> progress;
  const std::atomic<bool>* cancel = nullptr;
  double max_seconds = 0.0;
};

}  // namespace poreshell
