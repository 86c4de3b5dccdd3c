// The trilinear rule shared by the band's stencils, the shell's sampling, the multigrid's transfers and
// the sampled level set.

#include <gtest/gtest.h>

#include <array>
#include <random>

#include "core/trilinear.hpp"

namespace poreshell {
namespace {

TEST(Trilinear, CellHoldsThePointWithFractionsInTheUnitInterval) {
  for (const Vec3& q : {Vec3(0.25, 3.0, -1.5), Vec3(-0.0001, 7.999, 2.5), Vec3(-3.0, 0.0, 1e6 + 0.5)}) {
    const LatticeCell cell = lattice_cell(q);
    for (int a = 0; a < 3; ++a) {
      EXPECT_GE(cell.t[a], 0.0);
      EXPECT_LT(cell.t[a], 1.0);
    }
    EXPECT_LT((Vec3(cell.base.i, cell.base.j, cell.base.k) + cell.t - q).norm(), 1e-9);  // round-off
  }
}

TEST(Trilinear, WeightsSumToOneAndReproduceLinearFunctionsExactly) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(0.0, 1.0), coef(-5.0, 5.0);
  for (int trial = 0; trial < 200; ++trial) {
    const Vec3 t(u(rng), u(rng), u(rng)), g(coef(rng), coef(rng), coef(rng));
    const double c0 = coef(rng);
    double sum = 0.0, value = 0.0;
    for (int c = 0; c < 8; ++c) {
      const Vec3 corner((c & 1) ? 1 : 0, (c & 2) ? 1 : 0, (c & 4) ? 1 : 0);
      const double w = trilinear_weight(t, c);
      EXPECT_GE(w, 0.0);
      sum += w;
      value += w * (c0 + g.dot(corner));
    }
    EXPECT_NEAR(sum, 1.0, 1e-15);
    EXPECT_NEAR(value, c0 + g.dot(t), 1e-13);
  }
}

TEST(Trilinear, WeightsAtACornerPickThatCorner) {
  for (int corner = 0; corner < 8; ++corner) {
    const Vec3 t((corner & 1) ? 1 : 0, (corner & 2) ? 1 : 0, (corner & 4) ? 1 : 0);
    for (int c = 0; c < 8; ++c) EXPECT_EQ(trilinear_weight(t, c), c == corner ? 1.0 : 0.0);
  }
}

TEST(Trilinear, RowsGiveTheSameValueAsTheWeights) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(0.0, 1.0), value(-1.0, 1.0);
  for (int trial = 0; trial < 200; ++trial) {
    std::array<double, 8> f{};
    for (double& x : f) x = value(rng);
    const Vec3 t(u(rng), u(rng), u(rng));
    double by_weights = 0.0;
    for (int c = 0; c < 8; ++c) by_weights += trilinear_weight(t, c) * f[static_cast<std::size_t>(c)];
    const auto along_x = [&](int r) {
      const double* v = f.data() + 2 * r;
      return v[0] + t.x() * (v[1] - v[0]);
    };
    EXPECT_NEAR(trilinear_from_rows(along_x, t.y(), t.z()), by_weights, 1e-14);
  }
}

}  // namespace
}  // namespace poreshell
