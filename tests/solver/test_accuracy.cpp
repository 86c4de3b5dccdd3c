// Table 1 of the paper: spatial accuracy on the sphere of eq. (3.1). phi0 = -0.3 + 0.5 cos(2 pi x)
// cos(2 pi y) cos(2 pi z), dt = 1e-6, alpha = 1000, eps = 0.03, 30 steps; the error of grid h is taken
// against grid h/2 on the coarse points that lie in the fine band.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <numbers>

#include "band/band.hpp"
#include "solver/initial_condition.hpp"
#include "solver/reference_solver.hpp"

using namespace poreshell;

namespace {

struct Solution {
  NarrowBand band;
  std::vector<double> phi;
};

Solution solve_table1(int m) {
  const Grid grid(Vec3::Zero(), 1.0 / (m - 1), {m, m, m});
  Solution s{build_band(*make_paper_shape("sphere"), grid), {}};
  s.phi = sampled_initial_condition(s.band, [](const Vec3& p) {
    const double tau = 2 * std::numbers::pi;
    return -0.3 + 0.5 * std::cos(tau * p.x()) * std::cos(tau * p.y()) * std::cos(tau * p.z());
  });
  InnerOptions inner;
  inner.tolerance = 1e-11;  // far below the discretisation error being measured
  ReferenceSolver solver(s.band, ModelParameters{1000.0, 0.03, -0.3}, 1e-6, inner);
  for (int step = 0; step < 30; ++step) EXPECT_TRUE(solver.step(s.phi).converged);
  return s;
}

// RMS of phi_h - phi_{h/2} over the coarse points x_ijk that are in the fine band (Omega_R).
double restricted_error(const Solution& coarse, const Solution& fine) {
  double sum = 0.0;
  std::size_t count = 0;
  for (std::size_t v = 0; v < coarse.band.size(); ++v) {
    const Coord c = coarse.band.voxels()[v];
    const std::int64_t f = fine.band.find({2 * c.i, 2 * c.j, 2 * c.k});
    if (f < 0) continue;
    const double e = coarse.phi[v] - fine.phi[static_cast<std::size_t>(f)];
    sum += e * e;
    ++count;
  }
  EXPECT_GT(count, coarse.band.size() / 3);  // the fine band is half as thick
  return std::sqrt(sum / static_cast<double>(count));
}

}  // namespace

TEST(Accuracy, SecondOrderInSpaceAsInTable1) {
  const bool slow = std::getenv("PORESHELL_SLOW_TESTS") != nullptr;  // adds M = 257 (minutes)
  std::vector<int> sizes{33, 65, 129};
  if (slow) sizes.push_back(257);
  std::vector<Solution> solutions;
  for (int m : sizes) solutions.push_back(solve_table1(m));
  std::vector<double> errors;
  for (std::size_t i = 0; i + 1 < solutions.size(); ++i) {
    errors.push_back(restricted_error(solutions[i], solutions[i + 1]));
    std::printf("(1/%d, 1/%d): error %.4g\n", sizes[i] - 1, sizes[i + 1] - 1, errors.back());
  }
  for (std::size_t i = 0; i + 1 < errors.size(); ++i) {
    const double rate = std::log2(errors[i] / errors[i + 1]);
    std::printf("rate %.4f\n", rate);
    EXPECT_GE(rate, 1.75);
    // The paper's grids 33/65/129 give 1.94 here (paper: 1.95). The optional (1/128, 1/256) pair converges
    // faster than second order (rate 4.0, docs/benchmarks.md): most of this "error" is the relaxation of
    // the initial data's variation off the surface, whose time scale shrinks like h^4 / eps^2.
    if (i == 0) {
      EXPECT_LE(rate, 2.25);
    }
  }
}
