// Trim lines exact (issue 19, item 3): on an open surface the wall ends at the boundary curve for every
// offset. An open sleeve (r = 15 mm, 40 mm long, 1.5 mm wall, 3 mm rim so that no hole touches its
// ends) through perforate(): the output reaches no more than 0.1 mm beyond either end along the axis,
// `outside` has no vertex inside the sleeve's radius and `inside` none outside it. Before the wall was
// cut at the boundary, the unsigned distance made a rounded cap past each end (half the wall, plus the
// offset) that wrapped around the edge: 0.75 mm past each end centred, 1.5 mm with an offset, and the
// outside wall's wrapped end reached inside the surface.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "poreshell/poreshell.hpp"
#include "test_meshes.hpp"

using namespace poreshell;

namespace {

constexpr double kRadius = 15.0, kLength = 40.0, kWall = 1.5;

struct Extent {
  double z_min = 1e300, z_max = -1e300;
  double rho_min = 1e300, rho_max = -1e300;  // distance from the axis
};

Extent extent_of(const Mesh& mesh) {
  Extent e;
  for (const Point& p : mesh.vertices) {
    e.z_min = std::min(e.z_min, p[2]);
    e.z_max = std::max(e.z_max, p[2]);
    const double rho = std::hypot(p[0], p[1]);
    e.rho_min = std::min(e.rho_min, rho);
    e.rho_max = std::max(e.rho_max, rho);
  }
  return e;
}

// The polygon's faces lie at kRadius cos(pi / 96) between its vertices: the surface's own inner and
// outer reach from the axis.
constexpr double kFacetInset = kRadius * (1.0 - 0.99946459);  // 1 - cos(pi / 96)

void check_sleeve(WallOffset offset) {
  MeshInput input;
  input.mesh = test_support::open_sleeve(kRadius, kLength);  // 96 segments, 40 rings
  input.name = "sleeve";
  Options o;
  o.hole_diameter = 5.0;
  o.spacing = 8.0;
  o.wall = kWall;
  o.rim = 3.0;
  o.offset = offset;
  const Result r = perforate(input, o);
  ASSERT_EQ(r.outputs.size(), 1u);
  const Output& out = r.outputs[0];
  EXPECT_GT(out.holes.size(), 10u);
  const Extent e = extent_of(out.mesh);
  std::printf("offset %d: z from %.4f to %.4f mm (input 0 to %.1f), radius from %.4f to %.4f mm\n",
              static_cast<int>(offset), e.z_min, e.z_max, kLength, e.rho_min, e.rho_max);
  EXPECT_GE(e.z_min, -0.1) << "past the lower end";
  EXPECT_LE(e.z_max, kLength + 0.1) << "past the upper end";
  EXPECT_LE(e.z_min, 0.1) << "short of the lower end";
  EXPECT_GE(e.z_max, kLength - 0.1) << "short of the upper end";
  if (offset == WallOffset::outside) {
    EXPECT_GE(e.rho_min, kRadius - kFacetInset - 0.02) << "the outside wall pokes inside the surface";
  }
  if (offset == WallOffset::inside) {
    EXPECT_LE(e.rho_max, kRadius + 0.02) << "the inside wall pokes outside it";
  }
}

}  // namespace

TEST(TrimLines, CentredWallEndsAtTheBoundary) {
  check_sleeve(WallOffset::centered);
}

TEST(TrimLines, OutsideWallEndsAtTheBoundaryAndStaysOutside) {
  check_sleeve(WallOffset::outside);
}

TEST(TrimLines, InsideWallEndsAtTheBoundaryAndStaysInside) {
  check_sleeve(WallOffset::inside);
}
