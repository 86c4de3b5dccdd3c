// The reference solver solves the discrete equations (2.3)-(2.4): both relaxation orders reach the same
// fixed point, the residual is below the inner tolerance, and the result does not depend on the number
// of threads.

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include "band/band.hpp"
#include "solver/initial_condition.hpp"
#include "solver/reference_solver.hpp"
#include "solver/time_stepping.hpp"

using namespace poreshell;

namespace {

constexpr int kN = 33;

struct SmallSphere {
  Grid grid{Vec3::Zero(), 1.0 / (kN - 1), {kN, kN, kN}};
  NarrowBand band = build_band(*make_paper_shape("sphere"), grid);
  ModelParameters model{0.0764 / (epsilon_m(4, grid.h()) * epsilon_m(4, grid.h())), epsilon_m(4, grid.h()),
                        -0.3};
  double dt = 100 * grid.h();
};

std::vector<double> advance(const SmallSphere& s, InnerOptions inner, int steps, std::uint64_t seed = 3) {
  ReferenceSolver solver(s.band, s.model, s.dt, inner);
  std::vector<double> phi = random_initial_condition(s.band, -0.3, 0.5, seed);
  for (int n = 0; n < steps; ++n) EXPECT_TRUE(solver.step(phi).converged);
  return phi;
}

}  // namespace

TEST(ReferenceSolver, ResidualOfTheDiscreteEquationsIsBelowTheInnerTolerance) {
  const SmallSphere s;
  InnerOptions inner;
  inner.tolerance = 1e-9;
  ReferenceSolver solver(s.band, s.model, s.dt, inner);
  std::vector<double> phi = random_initial_condition(s.band, -0.3, 0.5, 1);
  for (int n = 0; n < 5; ++n) {
    const std::vector<double> old = phi;
    const StepReport report = solver.step(phi);
    ASSERT_TRUE(report.converged);
    const EquationResidual r =
        equation_residual(s.band, solver.laplacian(), s.model, s.dt, old, phi, solver.mu());
    EXPECT_LT(r.max(), 1e-9);
    EXPECT_GT(rms_difference(phi, old), 1e-4);  // the step did move phi
  }
}

TEST(ReferenceSolver, JacobiAndGaussSeidelReachTheSameSolution) {
  const SmallSphere s;
  InnerOptions gs, jacobi;
  gs.tolerance = jacobi.tolerance = 1e-10;
  jacobi.method = InnerIteration::jacobi;
  const std::vector<double> a = advance(s, gs, 4), b = advance(s, jacobi, 4);
  double diff = 0;
  for (std::size_t v = 0; v < a.size(); ++v) diff = std::max(diff, std::abs(a[v] - b[v]));
  EXPECT_LT(diff, 1e-7);
}

TEST(ReferenceSolver, ReportsNonConvergenceWhenTheSweepBudgetIsTooSmall) {
  const SmallSphere s;
  InnerOptions inner;
  inner.max_iterations = 3;
  ReferenceSolver solver(s.band, s.model, s.dt, inner);
  std::vector<double> phi = random_initial_condition(s.band, -0.3, 0.5, 1);
  EXPECT_FALSE(solver.step(phi).converged);
}

TEST(ReferenceSolver, SameResultWithOneAndAllThreads) {
  const SmallSphere s;
  std::vector<double> one, all;
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
    one = advance(s, {}, 3);
  }
  all = advance(s, {}, 3);
  ASSERT_EQ(one.size(), all.size());
  for (std::size_t v = 0; v < one.size(); ++v) ASSERT_EQ(one[v], all[v]) << v;
}

TEST(ReferenceSolver, StopsAtTheToleranceOnTheRmsChange) {
  const SmallSphere s;
  ReferenceSolver solver(s.band, s.model, s.dt);
  std::vector<double> phi = random_initial_condition(s.band, -0.3, 0.5, 5);
  RunOptions options;
  options.tolerance = 5e-3;
  options.max_steps = 500;
  const RunResult r = run_to_steady_state(solver, phi, nullptr, options);
  EXPECT_TRUE(r.reached_tolerance);
  EXPECT_LT(r.final_ec, 5e-3);
  EXPECT_LT(r.steps, 500);
}

TEST(InitialCondition, NoiseIsUniformOnMinusOneOneAndSeeded) {
  double sum = 0, lo = 1, hi = -1;
  for (std::int64_t k = 0; k < 100000; ++k) {
    const double u = uniform_noise(42, k);
    sum += u;
    lo = std::min(lo, u);
    hi = std::max(hi, u);
  }
  EXPECT_NEAR(sum / 100000, 0.0, 0.01);
  EXPECT_LT(lo, -0.999);
  EXPECT_GT(hi, 0.999);
  EXPECT_GE(lo, -1.0);
  EXPECT_LT(hi, 1.0);
  EXPECT_EQ(uniform_noise(42, 17), uniform_noise(42, 17));
  EXPECT_NE(uniform_noise(42, 17), uniform_noise(43, 17));
}
