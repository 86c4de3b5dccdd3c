#pragma once
// Shared by the pattern tests: the paper's section 3.2 run on a CI-sized band, with alpha scaled so
// that alpha eps_4^2 keeps the paper's value at N = 131 (the pattern depends on alpha eps^2 and eps).

#include <gtest/gtest.h>

#include <cstdint>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "band/band.hpp"
#include "pattern/pattern.hpp"
#include "solver/fast_solver.hpp"
#include "solver/initial_condition.hpp"
#include "solver/reference_solver.hpp"
#include "solver/time_stepping.hpp"

namespace poreshell::test_support {

struct PatternRun {
  SpotStats spots;
  std::vector<double> phi;
  int steps = 0;
};

// alpha as the paper would give it at N = 131 (1400 for the sphere), rescaled to this band's h.
// solver: "fast" (the default of the pipeline) or "reference".
inline PatternRun run_pattern(const NarrowBand& band, double paper_alpha, std::uint64_t seed,
                              const char* label, const std::string& solver_name = "fast") {
  const double eps = epsilon_m(4, band.grid().h());
  const double eps131 = epsilon_m(4, 1.0 / 130);
  const ModelParameters model{paper_alpha * (eps131 * eps131) / (eps * eps), eps, -0.3};
  const double dt = 100 * band.grid().h();
  std::unique_ptr<TimeStepper> solver;
  if (solver_name == "reference")
    solver = std::make_unique<ReferenceSolver>(band, model, dt);
  else
    solver = std::make_unique<FastSolver>(band, model, dt);
  PatternRun r;
  r.phi = random_initial_condition(band, -0.3, 0.5, seed);
  RunOptions options;
  options.tolerance = 1e-3;
  options.max_steps = 1500;
  options.min_spread = 1.0;  // as the pipeline does: never stop before the phases separate
  const RunResult result = run_to_steady_state(*solver, r.phi, nullptr, options);
  EXPECT_TRUE(result.reached_tolerance) << label << " seed " << seed;
  EXPECT_TRUE(result.inner_converged) << label << " seed " << seed;
  r.steps = result.steps;
  r.spots = spot_statistics(band, r.phi, 0.0);
  std::printf(
      "%s, %s, alpha(paper) %g, seed %llu: %d steps, %lld spots, size CV %.3f, spacing CV %.3f, area "
      "fraction "
      "%.3f\n",
      label, solver->name().c_str(), paper_alpha, static_cast<unsigned long long>(seed), r.steps,
      static_cast<long long>(r.spots.count), r.spots.size_cv, r.spots.spacing_cv, r.spots.area_fraction);
  return r;
}

}  // namespace poreshell::test_support
