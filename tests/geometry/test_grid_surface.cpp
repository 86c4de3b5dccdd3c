#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "core/error.hpp"
#include "core/grid.hpp"
#include "geometry/surface.hpp"

using namespace poreshell;

TEST(Grid, KeyAndCoordRoundTripOnNonCubicGrid) {
  const Grid grid(Vec3(-1.0, 2.0, 0.5), 0.25, {17, 23, 31});
  for (int k : {0, 5, 30})
    for (int j : {0, 7, 22})
      for (int i : {0, 3, 16}) {
        const Coord c{i, j, k};
        EXPECT_EQ(grid.coord(grid.key(c)), c);
        const Vec3 p = grid.position(c);
        EXPECT_DOUBLE_EQ(p.x(), -1.0 + 0.25 * i);
        EXPECT_DOUBLE_EQ(p.y(), 2.0 + 0.25 * j);
        EXPECT_DOUBLE_EQ(p.z(), 0.5 + 0.25 * k);
      }
  EXPECT_FALSE(grid.contains({17, 0, 0}));
  EXPECT_FALSE(grid.contains({0, -1, 0}));
  EXPECT_TRUE(grid.contains({16, 22, 30}));
}

TEST(Grid, FittedGridMatchesThePapersH) {
  const Grid g = Grid::fitted({Vec3::Zero(), Vec3::Ones()}, 131);
  EXPECT_DOUBLE_EQ(g.h(), 1.0 / 130.0);
  EXPECT_EQ(g.dims(), (std::array<int, 3>{131, 131, 131}));
  const Grid box = Grid::fitted({Vec3::Zero(), Vec3(2.0, 1.0, 0.5)}, 21);
  EXPECT_EQ(box.dims(), (std::array<int, 3>{21, 11, 6}));
  EXPECT_THROW(Grid::fitted({Vec3::Zero(), Vec3::Ones()}, 2), OptionError);
}

// Distance is 1-Lipschitz and the closest point lies on the surface at that distance.
void check_surface(const Surface& s, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int n = 0; n < 2000; ++n) {
    const Vec3 p(u(rng), u(rng), u(rng));
    const Vec3 cp = *s.closest_point(p);
    EXPECT_NEAR(std::abs(s.distance(cp)), 0.0, 1e-12);
    EXPECT_NEAR((p - cp).norm(), std::abs(s.distance(p)), 1e-12);
    const Vec3 q(u(rng), u(rng), u(rng));
    EXPECT_LE(std::abs(s.distance(p) - s.distance(q)), (p - q).norm() + 1e-12);
  }
}

TEST(Surface, SphereOfEq31) {
  const auto s = make_paper_shape("sphere");
  EXPECT_NEAR(s->distance(Vec3(0.5, 0.5, 0.5)), -0.3, 1e-15);
  EXPECT_NEAR(s->distance(Vec3(0.9, 0.5, 0.5)), 0.1, 1e-15);
  check_surface(*s, 1);
}

TEST(Surface, TorusOfSection32) {
  const auto s = make_paper_shape("torus");
  EXPECT_NEAR(s->distance(Vec3(0.8, 0.5, 0.5)), -0.15, 1e-15);  // on the core circle
  EXPECT_NEAR(s->distance(Vec3(0.5, 0.5, 0.5)), 0.15, 1e-15);   // the hole's centre
  check_surface(*s, 2);
  EXPECT_THROW(make_paper_shape("cube"), InputError);
}
