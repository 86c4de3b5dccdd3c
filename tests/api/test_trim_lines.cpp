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
// The isosurface keeps each vertex 0.05 of its edge from a grid point: where the surface passes a grid
// point closer than that, the vertex lies up to 0.05 of a cube's diagonal beyond it (cells of kWall / 3).
constexpr double kClamp = 0.05 * 1.7320508 * kWall / 3.0;

// How far the triangles near the ends (centroid within 2 cells of an end) cut the edges where the end
// faces meet the wall's: the 95th percentile, over their centroids and edge midpoints, of the distance
// to the nearest of the four faces (the wall's two cylinders, the two end planes). Every vertex lies on
// a face; a triangle across an edge with no vertex on it is a chamfer, its centroid off all of them.
double end_edge_cut(const Mesh& mesh, WallOffset offset) {
  const double inner = offset == WallOffset::outside  ? kRadius
                       : offset == WallOffset::inside ? kRadius - kWall
                                                      : kRadius - 0.5 * kWall;
  const double outer = inner + kWall;
  std::vector<double> off;
  const auto add = [&](const Point& p) {
    const double rho = std::hypot(p[0], p[1]);
    off.push_back(
        std::min({std::abs(rho - inner), std::abs(rho - outer), std::abs(p[2]), std::abs(kLength - p[2])}));
  };
  for (const Triangle& t : mesh.triangles) {
    const auto& a = mesh.vertices[static_cast<std::size_t>(t[0])];
    const auto& b = mesh.vertices[static_cast<std::size_t>(t[1])];
    const auto& c = mesh.vertices[static_cast<std::size_t>(t[2])];
    const auto mid = [](const Point& p, const Point& q, const Point& r, double wr) {
      const double wp = (1.0 - wr) / 2.0;
      return Point{wp * (p[0] + q[0]) + wr * r[0], wp * (p[1] + q[1]) + wr * r[1],
                   wp * (p[2] + q[2]) + wr * r[2]};
    };
    const Point centroid = mid(a, b, c, 1.0 / 3.0);
    if (std::min(centroid[2], kLength - centroid[2]) > 2.0 * kWall / 3.0) continue;
    add(centroid);
    add(mid(a, b, c, 0.0));
    add(mid(b, c, a, 0.0));
    add(mid(c, a, b, 0.0));
  }
  if (off.empty()) return 0.0;
  const auto p95 = off.begin() + static_cast<std::ptrdiff_t>(0.95 * static_cast<double>(off.size()));
  std::nth_element(off.begin(), p95, off.end());
  return *p95;
}

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
  // The isosurface's own creases (end_edge_cut() is a percentile over triangles, which a reduction
  // thins out on the flat faces; the reduced mesh is within max_deviation of this one).
  o.max_deviation = 0.0;
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
    EXPECT_GE(e.rho_min, kRadius - kFacetInset - kClamp) << "the outside wall pokes inside the surface";
  }
  if (offset == WallOffset::inside) {
    EXPECT_LE(e.rho_max, kRadius + kClamp) << "the inside wall pokes outside it";
  }
  // Vertices on the creases where the end faces meet the wall's (isosurface.hpp, `sharp_creases`): the
  // 95th percentile 0.022-0.025 mm; with the edges chamfered 0.0625 mm, and 0.08-0.12 mm where the ends lay
  // on grid planes (cells of 0.5 mm).
  const double cut = end_edge_cut(out.mesh, offset);
  std::printf("offset %d: the triangles at the ends' edges 0.95 within %.4f mm of a face\n",
              static_cast<int>(offset), cut);
  EXPECT_LT(cut, 0.05) << "the edges where the end faces meet the wall are chamfered";
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
