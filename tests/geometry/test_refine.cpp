// Splitting long edges for painting a field on a mesh: every edge ends up short, the surface and its
// topology stay as they were (no T-junctions: a closed mesh stays closed, its Euler characteristic
// unchanged), and the triangle budget holds.

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>

#include "geometry/mesh.hpp"
#include "geometry/refine.hpp"

using namespace poreshell;

namespace {

double longest_edge(const TriangleMesh& m) {
  double longest = 0.0;
  for (const Triangle& t : m.triangles)
    for (std::size_t k = 0; k < 3; ++k)
      longest = std::max(longest, (m.vertices[static_cast<std::size_t>(t[k])] -
                                   m.vertices[static_cast<std::size_t>(t[(k + 1) % 3])])
                                      .norm());
  return longest;
}

// A tetrahedron with edges of 9 to 13 units, outward.
TriangleMesh tetrahedron() {
  TriangleMesh m;
  m.vertices = {{0, 0, 0}, {10, 0, 0}, {0, 9, 0}, {1, 2, 8}};
  m.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  return m;
}

}  // namespace

TEST(SplitLongEdges, AClosedMeshStaysClosedWithItsShapeAndEveryEdgeShort) {
  const TriangleMesh input = tetrahedron();
  const MeshTopology before = analyze_topology(input);
  const TriangleMesh split = split_long_edges(input, 1.0, 1'000'000);
  const MeshTopology after = analyze_topology(split);
  EXPECT_LE(longest_edge(split), 1.0);
  EXPECT_GT(split.triangles.size(), 100u);
  EXPECT_TRUE(after.closed());
  EXPECT_TRUE(after.manifold());
  EXPECT_TRUE(after.oriented());
  EXPECT_EQ(after.components, 1);
  EXPECT_EQ(after.euler_characteristic, before.euler_characteristic);
  EXPECT_NEAR(surface_area(split), surface_area(input), 1e-9 * surface_area(input));
  EXPECT_NEAR(after.signed_volume, before.signed_volume, 1e-9 * before.signed_volume);
  for (std::size_t v = 0; v < input.vertices.size(); ++v) EXPECT_EQ(split.vertices[v], input.vertices[v]);
}

// A CAD export's strip, two long thin triangles: split into a disc with the same boundary length.
TEST(SplitLongEdges, AnOpenStripKeepsItsBoundaryAndOrientation) {
  TriangleMesh strip;
  strip.vertices = {{0, 0, 0}, {40, 0, 0}, {40, 2, 0}, {0, 2, 0}};
  strip.triangles = {{0, 1, 2}, {0, 2, 3}};
  const TriangleMesh split = split_long_edges(strip, 1.5, 1'000'000);
  const MeshTopology t = analyze_topology(split);
  EXPECT_LE(longest_edge(split), 1.5);
  EXPECT_EQ(t.euler_characteristic, 1);
  EXPECT_EQ(t.components, 1);
  EXPECT_TRUE(t.oriented());
  EXPECT_TRUE(t.manifold());
  double boundary = 0.0;
  for (const Edge& e : boundary_edges(split))
    boundary +=
        (split.vertices[static_cast<std::size_t>(e[0])] - split.vertices[static_cast<std::size_t>(e[1])])
            .norm();
  EXPECT_NEAR(boundary, 84.0, 1e-9);
  for (const Triangle& tri : split.triangles) {  // every normal still +z
    const Vec3 n =
        (split.vertices[static_cast<std::size_t>(tri[1])] - split.vertices[static_cast<std::size_t>(tri[0])])
            .cross(split.vertices[static_cast<std::size_t>(tri[2])] -
                   split.vertices[static_cast<std::size_t>(tri[0])]);
    EXPECT_GT(n.z(), 0.0);
  }
}

TEST(SplitLongEdges, StopsBeforePassingTheBudgetAndLeavesShortEdgesAlone) {
  const TriangleMesh input = tetrahedron();
  const TriangleMesh capped = split_long_edges(input, 0.01, 200);
  EXPECT_LE(capped.triangles.size(), 200u);
  EXPECT_GT(capped.triangles.size(), 50u);  // rounds ran until the next would pass 200
  EXPECT_TRUE(analyze_topology(capped).closed());
  const TriangleMesh unchanged = split_long_edges(input, 20.0, 1'000'000);
  EXPECT_EQ(unchanged.triangles, input.triangles);
  EXPECT_EQ(unchanged.vertices.size(), input.vertices.size());
}
