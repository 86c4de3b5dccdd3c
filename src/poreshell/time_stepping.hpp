#pragma once
// Runs a time stepper until the consecutive change e_c = ||phi^{n+1} - phi^n||_2 drops below tol
// (section 3), with e_c the root mean square over the band voxels.

#include <functional>
#include <limits>
#include <span>
#include <vector>

#include "poreshell/energy.hpp"
#include "poreshell/time_stepper.hpp"

namespace poreshell {

struct StepProgress {
  int step = 0;
  double ec = 0.0;
  double energy = 0.0;  // NaN when not evaluated at this step
  StepReport inner;
};

struct RunOptions {
  int max_steps = 2000;
  double tolerance = 1e-3;
  int energy_every = 0;  // evaluate the energy every k steps (0: only at the start and the end)
  std::function<void(const StepProgress&)> on_step;
};

struct RunResult {
  int steps = 0;
  double final_ec = 0.0;
  bool reached_tolerance = false;
  bool inner_converged = true;  // every step reached its inner tolerance
  long long inner_iterations = 0;
  double energy_first = std::numeric_limits<double>::quiet_NaN();  // NaN when no energy was evaluated
  double energy_last = std::numeric_limits<double>::quiet_NaN();
  std::vector<std::pair<int, double>> energy_trace;  // (step, energy) where evaluated
};

// Root mean square of a - b.
double rms_difference(std::span<const double> a, std::span<const double> b);

RunResult run_to_steady_state(TimeStepper& stepper, std::vector<double>& phi, const EnergyFunctional* energy,
                              const RunOptions& options);

}  // namespace poreshell
