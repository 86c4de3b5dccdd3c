#include "solver/time_stepping.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/parallel.hpp"

namespace poreshell {

double rms_difference(std::span<const double> a, std::span<const double> b) {
  if (a.empty()) return 0.0;
  const double sum = deterministic_sum(a.size(), [&](std::size_t i) {
    const double d = a[i] - b[i];
    return d * d;
  });
  return std::sqrt(sum / static_cast<double>(a.size()));
}

bool uniform_state_unstable(double alpha, double epsilon, double phi_bar) {
  const double a = 1.0 - 3.0 * phi_bar * phi_bar;
  return a > 0.0 && a * a > 4.0 * alpha * epsilon * epsilon;
}

RunResult run_to_steady_state(TimeStepper& stepper, std::vector<double>& phi, const EnergyFunctional* energy,
                              const RunOptions& options) {
  RunResult result;
  if (energy) {
    result.energy_first = (*energy)(phi);
    result.energy_trace.emplace_back(0, result.energy_first);
  }
  if (options.stop) options.stop(0, phi);
  std::vector<double> previous;
  for (int step = 1; step <= options.max_steps; ++step) {
    previous = phi;
    StepProgress progress;
    progress.step = step;
    progress.inner = stepper.step(phi);
    progress.ec = rms_difference(phi, previous);
    result.steps = step;
    result.final_ec = progress.ec;
    result.inner_iterations += progress.inner.inner_iterations;
    if (progress.inner.repeats > 0) ++result.repeated_steps;
    result.inner_converged = result.inner_converged && progress.inner.converged;
    result.reached_tolerance = options.stop ? options.stop(step, phi) : progress.ec < options.tolerance;
    if (result.reached_tolerance && options.min_spread > 0.0) {
      const auto [lo, hi] = std::minmax_element(phi.begin(), phi.end());
      if (*hi - *lo < options.min_spread) {
        result.reached_tolerance = false;
        ++result.quiet_steps_passed;
      }
    }
    const bool last = result.reached_tolerance || step == options.max_steps;
    progress.energy = std::numeric_limits<double>::quiet_NaN();
    if (energy && (last || (options.energy_every > 0 && step % options.energy_every == 0))) {
      progress.energy = (*energy)(phi);
      result.energy_trace.emplace_back(step, progress.energy);
    }
    if (options.on_step) options.on_step(progress);
    if (!std::isfinite(progress.ec)) break;
    if (last) break;
  }
  if (energy) result.energy_last = result.energy_trace.back().second;
  return result;
}

}  // namespace poreshell
