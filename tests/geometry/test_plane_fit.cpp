// PCA plane fits: the normal of points on a plane is the plane's normal.

#include <gtest/gtest.h>

#include <Eigen/Geometry>  // cross(), unitOrthogonal()
#include <random>
#include <vector>

#include "geometry/plane_fit.hpp"

namespace poreshell {
namespace {

TEST(PlaneFit, PointsOnAPlaneGiveItsNormal) {
  std::mt19937 rng(11);
  std::normal_distribution<double> g;
  for (int trial = 0; trial < 20; ++trial) {
    const Vec3 n = Vec3(g(rng), g(rng), g(rng)).normalized();
    const Vec3 u = n.unitOrthogonal(), v = n.cross(u), origin(g(rng), g(rng), g(rng));
    std::vector<Vec3> points;
    Vec3 sum = Vec3::Zero();
    for (int i = 0; i < 30; ++i) {
      points.push_back(origin + 3.0 * g(rng) * u + g(rng) * v);
      sum += points.back();
    }
    const PlaneFit fit = fit_plane(points);
    EXPECT_NEAR(std::abs(fit.normal().dot(n)), 1.0, 1e-12);
    EXPECT_NEAR(fit.normal().norm(), 1.0, 1e-12);
    EXPECT_NEAR(std::abs(fit.major().dot(n)), 0.0, 1e-12);
    EXPECT_NEAR(std::abs(fit.minor().dot(n)), 0.0, 1e-12);
    EXPECT_NEAR(fit.variances[0], 0.0, 1e-10 * fit.variances[2]);
    EXPECT_LE(fit.variances[1], fit.variances[2]);
    EXPECT_TRUE(fit.centroid.isApprox(sum / 30.0, 1e-12));
  }
}

TEST(PlaneFit, IndicesPickTheirPoints) {
  // Points 0-3 on z = 1, the others far off it.
  const std::vector<Vec3> points{Vec3(0, 0, 1), Vec3(1, 0, 1), Vec3(0, 1, 1),
                                 Vec3(1, 1, 1), Vec3(5, 5, 9), Vec3(-4, 2, -7)};
  const std::vector<std::size_t> on_plane{0, 1, 2, 3};
  const PlaneFit fit = fit_plane(points, on_plane);
  EXPECT_NEAR(std::abs(fit.normal().z()), 1.0, 1e-12);
  EXPECT_TRUE(fit.centroid.isApprox(Vec3(0.5, 0.5, 1.0)));
}

TEST(PlaneFit, CollinearPointsHaveOneDirectionOfSpread) {
  std::vector<Vec3> points;
  for (int i = 0; i < 10; ++i) points.push_back(Vec3(1, 2, 3) * i);
  const PlaneFit fit = fit_plane(points);
  EXPECT_LE(fit.variances[1], 1e-12 * fit.variances[2]);
  EXPECT_NEAR(std::abs(fit.major().dot(Vec3(1, 2, 3).normalized())), 1.0, 1e-12);
}

}  // namespace
}  // namespace poreshell
