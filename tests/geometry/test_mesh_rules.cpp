// The shared mesh rules: degenerate triangles, boundary edges, surface area.

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>

#include "geometry/mesh.hpp"
#include "test_meshes.hpp"

namespace poreshell {
namespace {

// An open cylinder of radius 1 and height 1: `n` segments around, two rims of n edges each.
TriangleMesh open_cylinder(int n) {
  return test_support::to_triangle_mesh(test_support::open_sleeve(1.0, 1.0, n, 1));
}

TEST(DegenerateTriangles, RepeatedVertexOrZeroAreaWhateverTheScale) {
  EXPECT_TRUE(has_repeated_vertex({3, 4, 3}));
  EXPECT_FALSE(has_repeated_vertex({3, 4, 5}));
  for (const double s : {1e-6, 1.0, 1e6}) {
    EXPECT_FALSE(zero_area(Vec3(0, 0, 0), Vec3(s, 0, 0), Vec3(0, s, 0)));
    EXPECT_TRUE(zero_area(Vec3(0, 0, 0), Vec3(s, s, s), Vec3(2 * s, 2 * s, 2 * s)));  // collinear
    EXPECT_TRUE(zero_area(Vec3(s, 0, 0), Vec3(s, 0, 0), Vec3(0, s, 0)));              // coincident
  }
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_TRUE(zero_area(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(nan, 1, 0)));
  TriangleMesh m{{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(2, 0, 0), Vec3(0, 1, 0)},
                 {{0, 1, 3}, {0, 1, 2}, {0, 0, 3}}};
  EXPECT_FALSE(is_degenerate(m, m.triangles[0]));
  EXPECT_TRUE(is_degenerate(m, m.triangles[1]));
  EXPECT_TRUE(is_degenerate(m, m.triangles[2]));
  EXPECT_EQ(analyze_topology(m).degenerate_triangles, 2);
}

TEST(BoundaryEdges, AnOpenCylinderHasItsTwoRims) {
  const int n = 24;
  const TriangleMesh m = open_cylinder(n);
  const std::vector<Edge> edges = boundary_edges(m);
  ASSERT_EQ(edges.size(), 2u * n);
  EXPECT_EQ(static_cast<std::int64_t>(edges.size()), analyze_topology(m).boundary_edges);
  EXPECT_TRUE(std::is_sorted(edges.begin(), edges.end()));
  for (const Edge& e : edges) {
    EXPECT_LT(e[0], e[1]);
    // Both ends on the same rim, next to each other around it.
    EXPECT_EQ(e[0] / n, e[1] / n);
    const int step = (e[1] - e[0]) % n;
    EXPECT_TRUE(step == 1 || step == n - 1);
  }
}

TEST(BoundaryEdges, NoneOnAClosedSurfaceAndRepeatedVerticesLeftOut) {
  TriangleMesh m = open_cylinder(8);
  // Caps: fans from a centre on each rim.
  for (int z = 0; z < 2; ++z) {
    const auto c = static_cast<std::int32_t>(m.vertices.size());
    m.vertices.emplace_back(0, 0, z);
    for (int k = 0; k < 8; ++k) {
      const std::int32_t a = 8 * z + k, b = 8 * z + (k + 1) % 8;
      m.triangles.push_back(z ? std::array{c, a, b} : std::array{c, b, a});
    }
  }
  EXPECT_TRUE(boundary_edges(m).empty());
  m.triangles.push_back({0, 0, 5});  // a repeated vertex: its "edges" are none
  EXPECT_TRUE(boundary_edges(m).empty());
  m.triangles.erase(m.triangles.begin());  // a hole of one triangle: its three edges
  EXPECT_EQ(boundary_edges(m).size(), 3u);
  EXPECT_THROW(boundary_edges(3, {{0, 1, 3}}), std::out_of_range);
}

TEST(SurfaceArea, SumsTheTriangles) {
  const TriangleMesh square{{Vec3(0, 0, 0), Vec3(2, 0, 0), Vec3(2, 3, 0), Vec3(0, 3, 0)},
                            {{0, 1, 2}, {0, 2, 3}}};
  EXPECT_DOUBLE_EQ(surface_area(square), 6.0);
}

}  // namespace
}  // namespace poreshell
