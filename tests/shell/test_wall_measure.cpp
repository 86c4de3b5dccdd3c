// The wall measurement on a written mesh: a caliper across a hollow sphere reads its wall, geometry
// beyond the probes' reach changes no reading, and geometry within it does; probes through solid
// (where a part thinner than two walls filled up) are counted apart and leave the percentiles alone.

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "measure/wall_measure.hpp"

namespace poreshell {
namespace {

// A UV sphere of radius r about c, outward (inward if flipped).
void add_sphere(TriangleMesh& m, const Vec3& c, double r, bool flipped) {
  const int nu = 96, nv = 48;
  const auto first = static_cast<std::int32_t>(m.vertices.size());
  for (int j = 0; j <= nv; ++j)
    for (int i = 0; i < nu; ++i) {
      const double u = 2 * std::numbers::pi * i / nu, v = std::numbers::pi * j / nv;
      m.vertices.push_back(c + r * Vec3(std::sin(v) * std::cos(u), std::sin(v) * std::sin(u), std::cos(v)));
    }
  const auto at = [&](int i, int j) { return first + j * nu + (i % nu); };
  for (int j = 0; j < nv; ++j)
    for (int i = 0; i < nu; ++i) {
      std::array<std::int32_t, 3> a{at(i, j), at(i, j + 1), at(i + 1, j + 1)},
          b{at(i, j), at(i + 1, j + 1), at(i + 1, j)};
      if (flipped) {
        std::swap(a[1], a[2]);
        std::swap(b[1], b[2]);
      }
      m.triangles.push_back(a);
      m.triangles.push_back(b);
    }
}

std::vector<WallProbe> radial_probes(const Vec3& c, double r) {
  std::vector<WallProbe> probes;
  for (int n = 0; n < 40; ++n) {
    const double z = -0.9 + 1.8 * n / 39.0, a = 2.4 * n;  // a spiral, away from the poles
    const Vec3 dir(std::sqrt(1 - z * z) * std::cos(a), std::sqrt(1 - z * z) * std::sin(a), z);
    probes.push_back({c + r * dir, dir});
  }
  return probes;
}

TEST(WallMeasure, ReadsTheWallOfAHollowSphere) {
  TriangleMesh shell;
  add_sphere(shell, Vec3::Zero(), 12.0, false);
  add_sphere(shell, Vec3::Zero(), 10.0, true);
  const WallMeasurement m = measure_wall(shell, radial_probes(Vec3::Zero(), 11.0), 8.0);
  EXPECT_EQ(m.probes, 40u);
  // Chords of the tessellation sit inside the spheres: within a few hundredths of the 2 mm wall.
  EXPECT_NEAR(m.median, 2.0, 0.05);
  EXPECT_GT(m.min, 1.9);
  EXPECT_LT(m.max, 2.1);
}

// Geometry beyond the probes' reach, near (just past the reach) and far, leaves every reading as it was.
TEST(WallMeasure, GeometryBeyondReachChangesNothing) {
  TriangleMesh shell;
  add_sphere(shell, Vec3::Zero(), 12.0, false);
  add_sphere(shell, Vec3::Zero(), 10.0, true);
  const auto probes = radial_probes(Vec3::Zero(), 11.0);
  const WallMeasurement alone = measure_wall(shell, probes, 3.0);
  add_sphere(shell, Vec3(0, 0, 0), 15.5, false);   // 4.5 from the probes: beyond the reach of 3
  add_sphere(shell, Vec3(100, 0, 0), 5.0, false);  // far away
  const WallMeasurement with_more = measure_wall(shell, probes, 3.0);
  EXPECT_EQ(alone.probes, with_more.probes);
  EXPECT_EQ(alone.median, with_more.median);
  EXPECT_EQ(alone.min, with_more.min);
  EXPECT_EQ(alone.max, with_more.max);
  // Within reach it does count: a sheet inside the wall, 0.5 above the probes, is what a caliper meets.
  add_sphere(shell, Vec3::Zero(), 11.5, true);
  EXPECT_NEAR(measure_wall(shell, probes, 3.0).median, 1.5, 0.05);
}

// Two probes of 42 cross a solid ball of diameter 6 (3 walls): the maximum and the merged count show
// them, the 5th to 95th percentiles do not.
TEST(WallMeasure, CountsProbesThroughSolidApart) {
  TriangleMesh shell;
  add_sphere(shell, Vec3::Zero(), 12.0, false);
  add_sphere(shell, Vec3::Zero(), 10.0, true);
  const Vec3 ball(40, 0, 0);
  add_sphere(shell, ball, 3.0, false);
  auto probes = radial_probes(Vec3::Zero(), 11.0);
  probes.push_back({ball, Vec3(0.6, 0.8, 0)});
  probes.push_back({ball, Vec3(0, 0.6, 0.8)});
  const WallMeasurement m = measure_wall(shell, probes, 8.0);
  ASSERT_EQ(m.probes, 42u);
  EXPECT_NEAR(m.median, 2.0, 0.05);
  EXPECT_EQ(m.merged, 2u);
  EXPECT_NEAR(m.max, 6.0, 0.05);
  EXPECT_GT(m.low, 1.9);
  EXPECT_LT(m.high, 2.1);
  EXPECT_LE(m.min, m.low);
}

}  // namespace
}  // namespace poreshell
