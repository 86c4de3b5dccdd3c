// The fast solver: its band multigrid solves the shifted closest-point Laplacian exactly (compared with a
// sparse direct solve) at a rate that does not depend on h, its steps are deterministic, and its steady
// state is a steady state of the paper's equations (2.3)-(2.4).

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <Eigen/SparseLU>
#include <cmath>

#include "band/band.hpp"
#include "band/operators.hpp"
#include "pattern/pattern.hpp"
#include "solver/band_multigrid.hpp"
#include "solver/fast_solver.hpp"
#include "solver/initial_condition.hpp"
#include "solver/reference_solver.hpp"
#include "solver/time_stepping.hpp"

using namespace poreshell;

namespace {

struct Case {
  std::unique_ptr<Surface> surface;
  Grid grid;
  NarrowBand band;
  Case(const std::string& shape, int n)
      : surface(make_paper_shape(shape)),
        grid(Vec3::Zero(), 1.0 / (n - 1), {n, n, n}),
        band(build_band(*surface, grid)) {}
};

// The paper's section 3.2 model on this grid, alpha scaled to keep alpha eps^2 = 0.076.
ModelParameters paper_model(const Grid& grid) {
  const double eps = epsilon_m(4, grid.h());
  return {0.0764 / (eps * eps), eps, -0.3};
}

double max_abs_difference(std::span<const double> a, std::span<const double> b) {
  double m = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) m = std::max(m, std::abs(a[i] - b[i]));
  return m;
}

}  // namespace

// The level transfers interpolate linear functions exactly, in both storage forms: the compact one (all
// 8 corners in the band) at closest points, and the renormalised partial one at points off the surface
// whose cells stick out of the band.
TEST(BandInterpolation, ExactForLinearFunctionsInBothForms) {
  const Case c("sphere", 41);
  const auto linear = [](const Vec3& p) { return 0.3 + 2.0 * p.x() - 1.5 * p.y() + 0.7 * p.z(); };
  std::vector<double> values(c.band.size());
  for (std::size_t v = 0; v < c.band.size(); ++v) values[v] = linear(c.grid.position(c.band.voxels()[v]));
  std::vector<Vec3> points;
  for (int i = 0; i < 200; ++i) {
    const double u = 0.1 + 0.031 * i, w = 0.7 + 0.017 * i;
    const Vec3 on_sphere =
        Vec3(0.5, 0.5, 0.5) +
        kPaperShapeRadius * Vec3(std::sin(u) * std::cos(w), std::sin(u) * std::sin(w), std::cos(u));
    points.push_back(on_sphere);
  }
  // Off the surface by 1.6 h: cells there reach out of the band (delta = 1.9 h), so some corners are missing.
  std::size_t partial = 0;
  const std::size_t on_surface = points.size();
  for (std::size_t i = 0; i < on_surface; ++i) {
    const Vec3 out = points[i] + 1.6 * c.grid.h() * (points[i] - Vec3(0.5, 0.5, 0.5)).normalized();
    const PointStencil s = interpolation_stencil(c.band, out);
    if (s.present_weight > 1e-3 && s.present_weight < 1.0) {
      points.push_back(out);
      ++partial;
    }
  }
  ASSERT_GT(partial, 10u);
  const BandInterpolation transfer(c.band, points);
  for (std::size_t i = 0; i < on_surface; ++i)
    EXPECT_NEAR(transfer.at<double>(i, values), linear(points[i]), 1e-6) << "compact form, point " << i;
  // The partial form renormalises the present corners' weights: exact where a linear function's values
  // are, i.e. it interpolates the same function as PointStencil.
  for (std::size_t i = on_surface; i < points.size(); ++i)
    EXPECT_NEAR(transfer.at<double>(i, values), interpolation_stencil(c.band, points[i]).interpolate(values),
                1e-6)
        << "partial form, point " << i;
}

// (z - L) x = b against Eigen's SparseLU on the same ghost-eliminated matrix, for the two shifts the
// fast solver uses at the paper's parameters (z h^2 ~ 0.04 and ~ 1) and on a sphere and a torus.
TEST(BandMultigrid, SolvesTheShiftedLaplacianLikeADirectSolver) {
  for (const char* shape : {"sphere", "torus"}) {
    const Case c(shape, 41);
    const double h2 = c.grid.h() * c.grid.h();
    for (double zh2 : {0.04, 1.0}) {
      const double z = zh2 / h2;
      BandMultigrid mg(c.band, z);
      EXPECT_GE(mg.level_count(), zh2 < 0.1 ? 3 : 1) << shape;
      std::vector<double> b = random_initial_condition(c.band, 0.0, 1.0, 5), x(c.band.size(), 0.0);
      for (double& v : b) v *= z;  // O(1) solution
      const MultigridSolveReport report = mg.solve(z, b, x, 1e-10 * z, 40);
      ASSERT_TRUE(report.converged) << shape << " z h^2 = " << zh2;
      EXPECT_LE(report.cycles, 14) << shape << " z h^2 = " << zh2;

      const auto n = static_cast<Eigen::Index>(c.band.size());
      SparseMatrix a = -laplacian_matrix(c.band);
      for (Eigen::Index i = 0; i < n; ++i) a.coeffRef(i, i) += z;
      Eigen::SparseLU<SparseMatrix> lu(a);
      ASSERT_EQ(lu.info(), Eigen::Success);
      const Eigen::VectorXd exact = lu.solve(Eigen::Map<const Eigen::VectorXd>(b.data(), n));
      // The rows of z - L sum to z with non-positive off-diagonals: |error| <= |residual| / z.
      EXPECT_LE(max_abs_difference(x, {exact.data(), x.size()}), report.residual / z + 1e-12)
          << shape << " z h^2 = " << zh2;
    }
  }
}

// Multigrid's point: the cycles needed do not grow as the grid is refined.
TEST(BandMultigrid, CyclesDoNotGrowWithResolution) {
  std::vector<int> cycles;
  for (int n : {49, 97, 129}) {
    const Case c("sphere", n);
    const double z = 0.04 / (c.grid.h() * c.grid.h());
    BandMultigrid mg(c.band, z);
    std::vector<double> b = random_initial_condition(c.band, 0.0, z, 9), x(c.band.size(), 0.0);
    const MultigridSolveReport report = mg.solve(z, b, x, 1e-8 * z, 60);
    ASSERT_TRUE(report.converged) << "N = " << n;
    cycles.push_back(report.cycles);
    std::printf("N = %d: %zu band voxels, %d levels, %d V-cycles to 1e-8\n", n, c.band.size(),
                mg.level_count(), report.cycles);
  }
  EXPECT_LE(cycles[2], cycles[0] + 2);
  EXPECT_LE(cycles[1], cycles[0] + 2);
}

// A run to the paper's tolerance ends near a steady state of the paper's scheme: the reference solver
// (eqs. 2.3-2.4 solved to 1e-10), started from the fast solver's final state, meets the same stopping
// rule within a few steps and keeps the pattern. (The pointwise residual of (2.3)-(2.4) at a state with
// e_c ~ 1e-3 is dominated by dt L of the last change, about 1e4 times e_c at these parameters, so the
// paper's own scheme is the sharper judge.)
TEST(FastSolver, EndsInASteadyStateOfThePapersEquations) {
  const Case c("sphere", 33);
  const ModelParameters model = paper_model(c.grid);
  const double dt = 100 * c.grid.h();
  RunOptions options;
  options.tolerance = 1e-3;
  options.max_steps = 1500;
  for (std::uint64_t seed : {2, 3}) {
    FastSolver fast(c.band, model, dt);
    std::vector<double> phi = random_initial_condition(c.band, -0.3, 0.5, seed);
    const RunResult run = run_to_steady_state(fast, phi, nullptr, options);
    ASSERT_TRUE(run.reached_tolerance);
    EXPECT_TRUE(run.inner_converged);
    const SpotStats spots = spot_statistics(c.band, phi, 0.0);

    InnerOptions inner;
    inner.tolerance = 1e-10;
    ReferenceSolver reference(c.band, model, dt, inner);
    std::vector<double> first_step = phi;
    reference.step(first_step);
    const double first_change = rms_difference(first_step, phi);
    const RunResult after = run_to_steady_state(reference, phi, nullptr, options);
    std::printf(
        "seed %llu: fast %d steps, %lld spots; reference from there: first change %.2e, %d steps to "
        "tol, %lld spots\n",
        static_cast<unsigned long long>(seed), run.steps, static_cast<long long>(spots.count), first_change,
        after.steps, static_cast<long long>(spot_statistics(c.band, phi, 0.0).count));
    EXPECT_LT(first_change, 3 * options.tolerance);
    EXPECT_LE(after.steps, 30);
    EXPECT_EQ(spot_statistics(c.band, phi, 0.0).count, spots.count);
  }
}

TEST(FastSolver, SameResultForOneAndTwoThreads) {
  const Case c("torus", 41);
  const ModelParameters model = paper_model(c.grid);
  auto advance = [&](int threads) {
    const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    FastSolver fast(c.band, model, 100 * c.grid.h());
    std::vector<double> phi = random_initial_condition(c.band, -0.3, 0.5, 4);
    for (int s = 0; s < 20; ++s) fast.step(phi);
    return phi;
  };
  const std::vector<double> one = advance(1), two = advance(2);
  EXPECT_EQ(one, two);
}

TEST(FastSolver, StabilisationCoversTheStepAndKeepsTheShiftsReal) {
  const Case c("sphere", 33);
  const ModelParameters model = paper_model(c.grid);
  for (double dt_in_h : {0.01, 0.1, 10.0, 1000.0}) {
    FastSolver fast(c.band, model, dt_in_h * c.grid.h());
    std::vector<double> phi = random_initial_condition(c.band, -0.3, 0.5, 6);
    for (int s = 0; s < 30; ++s) {
      const std::vector<double> old = phi;
      fast.step(phi);
      double max_square = 0.0;
      for (std::size_t v = 0; v < phi.size(); ++v)
        max_square = std::max({max_square, phi[v] * phi[v], old[v] * old[v]});
      // Energy stability needs S >= f'(xi)/2 on every segment [phi^n, phi^{n+1}].
      EXPECT_GE(fast.stabilisation(), 0.5 * (3 * max_square - 1) - 1e-12) << "dt = " << dt_in_h << "h";
    }
    EXPECT_GT(fast.shift_small(), 0.0);
    EXPECT_GE(fast.shift_large(), fast.shift_small());
    // z1 z2 = (1/dt + alpha) / eps^2 and z1 + z2 = S / eps^2.
    const double eps2 = model.epsilon * model.epsilon, dt = dt_in_h * c.grid.h();
    EXPECT_NEAR(fast.shift_small() * fast.shift_large() * eps2 / (1 / dt + model.alpha), 1.0, 1e-9);
    EXPECT_NEAR((fast.shift_small() + fast.shift_large()) * eps2 / fast.stabilisation(), 1.0, 1e-9);
  }
}

// S is chosen from phi^n and the guess of phi^{n+1}, with a margin, so that a step is rarely repeated:
// with S from phi^n alone, the pattern's creeping peaks made one step in five a repeat (bunny, N = 260).
// Here, with alpha eps^2 where S sits above the real-root floor once the spots form, the run to the
// tolerance repeats 1 of its 218 steps (98 repeated solves in 220 steps with S from phi^n alone).
TEST(FastSolver, StabilisationRarelyNeedsARepeat) {
  const Case c("sphere", 49);
  ModelParameters model = paper_model(c.grid);
  model.alpha *= 0.4;  // alpha eps^2 = 0.03, as for the bunny's alpha on the 260 grid: floor 0.35
  FastSolver fast(c.band, model, 100 * c.grid.h());
  std::vector<double> phi = random_initial_condition(c.band, -0.3, 0.5, 4);
  RunOptions options;
  options.tolerance = 1e-3;
  options.max_steps = 1500;
  const RunResult run = run_to_steady_state(fast, phi, nullptr, options);
  ASSERT_TRUE(run.reached_tolerance);
  std::printf("%d steps, %d repeated, final S %.3f, shifts %.4g and %.4g\n", run.steps, run.repeated_steps,
              fast.stabilisation(), fast.shift_small(), fast.shift_large());
  // The premise: S above the real-root floor, where the two shifts coincide.
  EXPECT_GT(fast.shift_large(), 2.0 * fast.shift_small());
  EXPECT_LE(run.repeated_steps, run.steps / 20);  // the report's solver.repeated_steps
}
