#pragma once
// Runs a time stepper until the consecutive change e_c = ||phi^{n+1} - phi^n||_2 drops below tol
// (section 3), with e_c the root mean square over the band voxels, once the phases have separated.

#include <functional>
#include <limits>
#include <span>
#include <utility>
#include <vector>

#include "solver/energy.hpp"
#include "solver/time_stepper.hpp"

namespace poreshell {

struct StepProgress {
  int step = 0;
  double ec = 0.0;
  double energy = 0.0;  // NaN when not evaluated at this step
  StepReport inner;
  bool coarse = false;  // a step of the coarse start's run (coarse_start.hpp)
};

struct RunOptions {
  int max_steps = 2000;
  double tolerance = 1e-3;
  int energy_every = 0;  // evaluate the energy every k steps (0: only at the start and the end)
  // Do not stop before the phases have separated (max phi - min phi >= min_spread). Where the uniform
  // state is unstable, the pattern grows slowly out of the decayed noise, and e_c can dip below the
  // tolerance in that quiet phase; stopping there returns no pattern at all. 0: off.
  double min_spread = 0.0;
  std::function<void(const StepProgress&)> on_step;
  // Another stop rule in place of e_c < tolerance (e.g. solver/hole_stop.hpp): called with phi before
  // the first step (step 0) and after each step; true ends the run (reached_tolerance then says so).
  std::function<bool(int step, std::span<const double> phi)> stop;
};

struct RunResult {
  int steps = 0;
  double final_ec = 0.0;
  bool reached_tolerance = false;
  int quiet_steps_passed = 0;   // steps with e_c < tol that did not stop the run (phases not separated)
  bool inner_converged = true;  // every step reached its inner tolerance
  long long inner_iterations = 0;
  int repeated_steps = 0;                                          // steps solved more than once
  double energy_first = std::numeric_limits<double>::quiet_NaN();  // NaN when no energy was evaluated
  double energy_last = std::numeric_limits<double>::quiet_NaN();
  std::vector<std::pair<int, double>> energy_trace;  // (step, energy) where evaluated
};

// Whether the uniform state phi_bar is linearly unstable, so that a pattern must form:
// (1 - 3 phi_bar^2)^2 > 4 alpha eps^2.
bool uniform_state_unstable(double alpha, double epsilon, double phi_bar);

// Root mean square of a - b.
double rms_difference(std::span<const double> a, std::span<const double> b);

RunResult run_to_steady_state(TimeStepper& stepper, std::vector<double>& phi, const EnergyFunctional* energy,
                              const RunOptions& options);

}  // namespace poreshell
