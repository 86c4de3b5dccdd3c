// The layout tools (pattern/layout.hpp) on a sphere's band: the surface's area from its samples, the
// cell-area CV of layouts known to be even or not, Lloyd's iteration making an uneven layout even on
// the surface, whatever the thread count, and the disc field the equation restarts from.

#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>

#include "band/band.hpp"
#include "pattern/layout.hpp"
#include "pattern/pattern.hpp"

namespace poreshell {
namespace {

constexpr double kRadius = 0.35;
const Vec3 kCentre = Vec3::Constant(0.5);

const Sphere& sphere() {
  static const Sphere s(kCentre, kRadius);
  return s;
}

const NarrowBand& band() {
  static const NarrowBand b = build_band(sphere(), Grid(Vec3::Zero(), 1.0 / 80, {81, 81, 81}));
  return b;
}

std::vector<Vec3> random_points_on_sphere(int n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> g;
  std::vector<Vec3> points;
  for (int i = 0; i < n; ++i) points.push_back(kCentre + kRadius * Vec3(g(rng), g(rng), g(rng)).normalized());
  return points;
}

TEST(Layout, AreaSamplesCarryTheSurfacesArea) {
  const AreaSamples s = area_samples(band());
  double area = 0.0;
  for (const double a : s.area) area += a;
  EXPECT_NEAR(area, 4.0 * std::numbers::pi * kRadius * kRadius, 0.01 * area);
  for (const Vec3& p : s.points) ASSERT_NEAR((p - kCentre).norm(), kRadius, 1e-9);
  // Solid zones give no samples: a weight of 1 on every voxel leaves none.
  EXPECT_TRUE(area_samples(band(), std::vector<double>(band().size(), 1.0)).points.empty());
}

TEST(Layout, CellAreaCvIsZeroForTheOctahedronAndLargeForRandomPoints) {
  const AreaSamples s = area_samples(band());
  std::vector<Vec3> octahedron;
  for (int axis = 0; axis < 3; ++axis)
    for (const double sign : {-1.0, 1.0}) octahedron.push_back(kCentre + sign * kRadius * Vec3::Unit(axis));
  EXPECT_LT(cell_area_cv(s, octahedron), 0.02);
  EXPECT_GT(cell_area_cv(s, random_points_on_sphere(100, 1)), 0.25);
  EXPECT_EQ(cell_area_cv(s, std::vector<Vec3>{kCentre}), 0.0);
}

TEST(Layout, LloydMakesRandomPointsEvenAndKeepsThemOnTheSurface) {
  const AreaSamples s = area_samples(band());
  const std::vector<Vec3> start = random_points_on_sphere(100, 2);
  const std::vector<Vec3> even = lloyd_centres(start, s, sphere(), 30);
  ASSERT_EQ(even.size(), start.size());
  for (const Vec3& p : even) EXPECT_NEAR((p - kCentre).norm(), kRadius, 1e-9);
  // Random: a cell-area CV above 0.25; after 30 iterations about 0.08, a third of it at most.
  EXPECT_LT(cell_area_cv(s, even), std::min(0.1, cell_area_cv(s, start) / 3.0)) << cell_area_cv(s, start);
}

TEST(Layout, LloydGivesTheSameCentresOnAnyThreadCount) {
  const AreaSamples s = area_samples(band());
  const std::vector<Vec3> start = random_points_on_sphere(60, 3);
  std::vector<Vec3> one, two;
  tbb::task_arena(1).execute([&] { one = lloyd_centres(start, s, sphere(), 10); });
  tbb::task_arena(2).execute([&] { two = lloyd_centres(start, s, sphere(), 10); });
  ASSERT_EQ(one.size(), two.size());
  for (std::size_t i = 0; i < one.size(); ++i) EXPECT_EQ(one[i], two[i]);
}

TEST(Layout, DiscFieldHasTheMeanAndThePhasesAtAndAwayFromTheCentres) {
  const std::vector<Vec3> centres{kCentre + kRadius * Vec3::UnitZ(), kCentre - kRadius * Vec3::UnitZ()};
  const double epsilon = 0.01, mean = -0.3;
  const std::vector<double> phi = disc_field(band(), centres, 0.08, epsilon, {}, mean);
  double sum = 0.0;
  for (const double p : phi) sum += p;
  EXPECT_NEAR(sum / static_cast<double>(phi.size()), mean, 1e-12);
  // Both phases, 2 apart (the profile's tanh), shifted alike to make the mean.
  double at_pole = -2.0, at_equator = 2.0;
  for (std::size_t v = 0; v < band().size(); ++v) {
    const Vec3 cp = band().closest_point(v);
    if ((cp - centres[0]).norm() < 0.02) at_pole = std::max(at_pole, phi[v]);
    if (std::abs(cp.z() - kCentre.z()) < 0.02) at_equator = std::min(at_equator, phi[v]);
  }
  EXPECT_GT(at_pole - at_equator, 1.9);
  EXPECT_LT(at_pole - at_equator, 2.0 + 1e-12);
}

TEST(Layout, DiscFieldKeepsSolidZonesSolidAndTheMean) {
  const std::vector<Vec3> centres{kCentre + kRadius * Vec3::UnitX()};
  std::vector<double> weight(band().size(), 0.0);
  for (std::size_t v = 0; v < band().size(); ++v)
    if (band().closest_point(v).z() > kCentre.z() + 0.2) weight[v] = 1.0;
  const double mean = -0.3;
  const std::vector<double> phi = disc_field(band(), centres, 0.08, 0.01, weight, mean);
  double sum = 0.0;
  for (std::size_t v = 0; v < phi.size(); ++v) {
    sum += phi[v];
    if (weight[v] == 1.0) {
      ASSERT_EQ(phi[v], -1.0);
    }
  }
  EXPECT_NEAR(sum / static_cast<double>(phi.size()), mean, 1e-12);
}

// The even layout at spacing a: about one hole per 1.058 a^2 of the sphere (the equation's density),
// more even than Lloyd makes random points, the same for a seed on any thread count, another for
// another seed; none in a zone or within its margin.
TEST(Layout, EvenLayoutHasTheEquationsDensityAndIsEvenAndSeeded) {
  const double a = 0.1, area = 4.0 * std::numbers::pi * kRadius * kRadius;
  std::vector<Vec3> one, two;
  tbb::task_arena(1).execute([&] { one = even_layout(band(), sphere(), {}, a, 7); });
  tbb::task_arena(2).execute([&] { two = even_layout(band(), sphere(), {}, a, 7); });
  EXPECT_EQ(one, two);
  EXPECT_NEAR(static_cast<double>(one.size()), area / (1.058 * a * a), 1.0);
  const AreaSamples s = area_samples(band());
  // 0.067 at these 146 holes on an 80-cell grid (random points after 30 Lloyd iterations: about 0.08).
  EXPECT_LT(cell_area_cv(s, one), 0.075);
  EXPECT_NE(even_layout(band(), sphere(), {}, a, 8), one);
  for (const Vec3& p : one) EXPECT_NEAR((p - kCentre).norm(), kRadius, 1e-9);
  // A solid cap above z = 0.2 from the centre: no centre in it or within 0.15 a of it, and fewer holes.
  std::vector<double> weight(band().size(), 0.0);
  for (std::size_t v = 0; v < band().size(); ++v)
    if (band().closest_point(v).z() > kCentre.z() + 0.2) weight[v] = 1.0;
  const std::vector<Vec3> capped = even_layout(band(), sphere(), weight, a, 7);
  EXPECT_LT(capped.size(), one.size());
  for (const Vec3& p : capped) EXPECT_LT(p.z(), kCentre.z() + 0.2 - 0.1 * a);
}

// Pinholes: of a disc 0.16 wide and one 0.06 wide, with 0.1 the least, the small one is made solid and
// the large one left as it is.
TEST(Layout, CloseSmallSpotsMakesPinholesSolidAndKeepsTheRest) {
  const Vec3 big = kCentre + kRadius * Vec3::UnitZ(), small = kCentre - kRadius * Vec3::UnitZ();
  const std::vector<double> a = disc_field(band(), std::vector<Vec3>{big}, 0.08, 0.01, {}, std::nullopt);
  const std::vector<double> b = disc_field(band(), std::vector<Vec3>{small}, 0.03, 0.01, {}, std::nullopt);
  std::vector<double> phi(a.size());
  for (std::size_t v = 0; v < phi.size(); ++v) phi[v] = std::max(a[v], b[v]);
  const std::vector<double> before = phi;
  ASSERT_EQ(spot_statistics(band(), phi, 0.0).count, 2);
  EXPECT_EQ(close_small_spots(band(), phi, 0.0, 0.1), 1);
  EXPECT_EQ(spot_statistics(band(), phi, 0.0).count, 1);
  for (std::size_t v = 0; v < phi.size(); ++v) {
    if ((band().closest_point(v) - big).norm() < 0.15) {
      ASSERT_EQ(phi[v], before[v]);
    }
    if (before[v] > 0.0 && (band().closest_point(v) - small).norm() < 0.05) {
      ASSERT_EQ(phi[v], -1.0);
    }
  }
  EXPECT_EQ(close_small_spots(band(), phi, 0.0, 0.1), 0);
}

}  // namespace
}  // namespace poreshell
