// The holes rule (docs/solver.md "Stop rules"): it stops only when count, centres and boundaries hold over
// its window (tests/pipeline/test_stop_rules.cpp: its holes against the paper rule's).

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "band/band.hpp"
#include "geometry/surface.hpp"
#include "solver/hole_stop.hpp"

using namespace poreshell;

TEST(HoleStop, LargestNearestDistance) {
  const std::vector<Vec3> a{{0, 0, 0}, {1, 0, 0}}, b{{0, 0.1, 0}, {1.3, 0, 0}, {5, 5, 5}};
  EXPECT_NEAR(largest_nearest_distance(a, b), 0.3, 1e-12);
  EXPECT_NEAR(largest_nearest_distance(b, a), (Vec3(5, 5, 5) - Vec3(1, 0, 0)).norm(), 1e-12);
  EXPECT_TRUE(std::isinf(largest_nearest_distance(a, {})));
  EXPECT_EQ(largest_nearest_distance({}, b), 0.0);
}

TEST(HoleStop, SettlesOnlyOnceTheLayoutHoldsOverTheWindow) {
  const Sphere sphere(Vec3::Constant(0.5), 0.35);
  const NarrowBand band = build_band(sphere, Grid::fitted(Box{Vec3::Zero(), Vec3::Ones()}, 48));
  // Two caps open: a fixed layout.
  std::vector<double> phi(band.size());
  for (std::size_t v = 0; v < band.size(); ++v) {
    const double z = band.grid().position(band.voxels()[v]).z() - 0.5;
    phi[v] = std::abs(z) > 0.25 ? 1.0 : -1.0;
  }
  HoleStopOptions o;
  o.every = 2;
  o.window = 6;
  HoleStop stop(band, o);
  for (int step = 0; step < 6; ++step) EXPECT_FALSE(stop.settled(step, phi)) << step;
  EXPECT_TRUE(stop.settled(6, phi));
  EXPECT_EQ(stop.last_check().holes, 2);
  EXPECT_EQ(stop.progress(), 1.0);

  // A cap that grows: its boundary moves, so the layout has not settled.
  HoleStop moving(band, o);
  bool settled = false;
  for (int step = 0; step <= 12; step += 2) {
    for (std::size_t v = 0; v < band.size(); ++v) {
      const double z = band.grid().position(band.voxels()[v]).z() - 0.5;
      phi[v] = z > 0.25 - 0.01 * step || z < -0.25 ? 1.0 : -1.0;
    }
    settled = settled || moving.settled(step, phi);
  }
  EXPECT_FALSE(settled);
  EXPECT_GT(moving.last_check().flipped, o.max_flipped);
  EXPECT_LT(moving.progress(), 1.0);
}

// The progress that the time left is said from: it grows while the layout holds, waits for the whole
// window, and stalls (never goes back) when the hole count changes, until the new count has held a window.
TEST(HoleStop, ProgressWaitsForTheWindowAndStallsWhenTheCountChanges) {
  const Sphere sphere(Vec3::Constant(0.5), 0.35);
  const NarrowBand band = build_band(sphere, Grid::fitted(Box{Vec3::Zero(), Vec3::Ones()}, 48));
  const auto layout = [&](bool third_cap) {
    std::vector<double> phi(band.size());
    for (std::size_t v = 0; v < band.size(); ++v) {
      const Vec3 x = band.grid().position(band.voxels()[v]) - Vec3::Constant(0.5);
      phi[v] = std::abs(x.z()) > 0.25 || (third_cap && x.x() > 0.3) ? 1.0 : -1.0;
    }
    return phi;
  };
  HoleStopOptions o;
  o.every = 2;
  o.window = 6;
  HoleStop stop(band, o);
  double before = 0.0;
  for (int step = 0; step <= 4; step += 2) {
    EXPECT_FALSE(stop.settled(step, layout(false))) << step;
    EXPECT_GT(stop.progress(), before) << step;
    EXPECT_LT(stop.progress(), 0.99) << step;
    before = stop.progress();
  }
  for (int step = 6; step <= 10; step += 2) {
    EXPECT_FALSE(stop.settled(step, layout(true))) << step;
    EXPECT_EQ(stop.last_check().holes, 3);
    EXPECT_EQ(stop.progress(), before) << "a new hole at step 6 holds the progress back, step " << step;
  }
  EXPECT_TRUE(stop.settled(12, layout(true)));
  EXPECT_EQ(stop.progress(), 1.0);
}
