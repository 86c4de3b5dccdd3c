// Thin parts and creases of an input mesh: a slab thinner than the limit is thin and a thick block is
// not; a cube's twelve edges are creases and a sphere has none.

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "geometry/mesh_surface.hpp"
#include "input/features.hpp"
#include "input/point_cloud.hpp"

using namespace poreshell;

namespace {

// An axis-aligned box [lo, hi], each face split into n x n quads (two triangles each), outward.
TriangleMesh box(const Vec3& lo, const Vec3& hi, int n) {
  TriangleMesh m;
  for (int axis = 0; axis < 3; ++axis)
    for (int side = 0; side < 2; ++side) {
      const int u = (axis + 1) % 3, v = (axis + 2) % 3;
      const auto base = static_cast<std::int32_t>(m.vertices.size());
      for (int i = 0; i <= n; ++i)
        for (int j = 0; j <= n; ++j) {
          Vec3 p;
          p[axis] = side ? hi[axis] : lo[axis];
          p[u] = lo[u] + (hi[u] - lo[u]) * i / n;
          p[v] = lo[v] + (hi[v] - lo[v]) * j / n;
          m.vertices.push_back(p);
        }
      for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
          const std::int32_t a = base + i * (n + 1) + j, b = a + n + 1, c = b + 1, d = a + 1;
          if (side) {
            m.triangles.push_back({a, b, c});
            m.triangles.push_back({a, c, d});
          } else {
            m.triangles.push_back({a, c, b});
            m.triangles.push_back({a, d, c});
          }
        }
    }
  return m;  // duplicate vertices along the box's edges: shared positions, not indices
}

TEST(Features, ASlabThinnerThanTheLimitIsThinAThickBlockIsNot) {
  const TriangleMesh slab = box(Vec3(0, 0, 0), Vec3(40, 40, 4), 16);
  const TriangleMesh block = box(Vec3(0, 0, 0), Vec3(40, 40, 40), 16);
  FeatureOptions o;
  o.thin_below = 12.0;  // 1.5 holes of 8
  for (const auto& [mesh, thin] : {std::pair{&slab, true}, std::pair{&block, false}}) {
    const MeshSurface surface(*mesh);
    const SurfaceFeatures f = find_surface_features(*mesh, surface, o);
    std::int64_t centre_marked = 0, centre = 0;
    for (std::size_t v = 0; v < mesh->vertices.size(); ++v) {
      const Vec3& p = mesh->vertices[v];
      if (std::abs(p.x() - 20) < 10 && std::abs(p.y() - 20) < 10 &&
          (p.z() == 0 || p.z() == mesh->vertices.back().z())) {
        ++centre;
        centre_marked += f.thin[v] > 0 ? 1 : 0;
      }
    }
    ASSERT_GT(centre, 0);
    EXPECT_EQ(centre_marked, thin ? centre : 0) << (thin ? "slab" : "block");
  }
}

// The same on a point cloud (the boxes' vertices as splats, their normals without a side): the slab's
// points are thin, the block's are not, although each point's neighbours lie within the ball's first
// depth (spacing 2.5, least depth 1.5): the test starts at twice the spacing.
TEST(Features, PointsOfASlabAreThinThoseOfAThickBlockAreNot) {
  FeatureOptions o;
  o.thin_below = 12.0;
  for (const auto& [mesh, thin] : {std::pair{box(Vec3(0, 0, 0), Vec3(40, 40, 4), 16), true},
                                   std::pair{box(Vec3(0, 0, 0), Vec3(40, 40, 40), 16), false}}) {
    const SplatSurface splats(mesh.vertices);
    const std::vector<double> marks =
        thin_points(splats.points(), splats.normals(), splats.radii(),
                    PointTree(std::vector<Vec3>(splats.points().begin(), splats.points().end())), splats, o);
    std::int64_t centre_marked = 0, centre = 0;
    for (std::size_t v = 0; v < splats.size(); ++v) {
      const Vec3& p = splats.points()[v];
      if (std::abs(p.x() - 20) < 10 && std::abs(p.y() - 20) < 10 &&
          (p.z() == 0 || p.z() == (thin ? 4 : 40))) {
        ++centre;
        centre_marked += marks[v] > 0 ? 1 : 0;
      }
    }
    ASSERT_GT(centre, 0);
    EXPECT_EQ(centre_marked, thin ? centre : 0) << (thin ? "slab" : "block");
  }
}

TEST(Features, ACubesEdgesAreCreasesASphereHasNone) {
  FeatureOptions o;
  o.crease_degrees = 40.0;
  o.min_crease_length = 5.0;
  TriangleMesh cube = box(Vec3(0, 0, 0), Vec3(20, 20, 20), 4);
  // Share the edge vertices so that the faces meet in edges with two triangles.
  std::vector<std::int32_t> remap(cube.vertices.size());
  std::vector<Vec3> unique;
  for (std::size_t v = 0; v < cube.vertices.size(); ++v) {
    std::size_t k = 0;
    while (k < unique.size() && (unique[k] - cube.vertices[v]).norm() > 1e-9) ++k;
    if (k == unique.size()) unique.push_back(cube.vertices[v]);
    remap[v] = static_cast<std::int32_t>(k);
  }
  for (auto& t : cube.triangles)
    for (auto& v : t) v = remap[static_cast<std::size_t>(v)];
  cube.vertices = unique;
  const SurfaceFeatures f = find_surface_features(cube, MeshSurface(cube), o);
  EXPECT_EQ(f.crease_edges, 12 * 4);  // every edge of the cube, in 4 pieces each
  double length = 0;
  for (const auto& s : f.creases) length += (s[1] - s[0]).norm();
  EXPECT_NEAR(length, 12 * 20.0, 1e-9);

  TriangleMesh sphere;  // a fine UV sphere: dihedral angles of a few degrees
  const int rings = 24, segments = 48;
  sphere.vertices.push_back(Vec3(0, 0, 10));
  for (int i = 1; i < rings; ++i)
    for (int j = 0; j < segments; ++j) {
      const double th = std::numbers::pi * i / rings, ph = 2 * std::numbers::pi * j / segments;
      sphere.vertices.push_back(10 *
                                Vec3(std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th)));
    }
  sphere.vertices.push_back(Vec3(0, 0, -10));
  const auto at = [&](int r, int j) { return 1 + (r - 1) * segments + j % segments; };
  const auto south = static_cast<std::int32_t>(sphere.vertices.size() - 1);
  for (int j = 0; j < segments; ++j) {
    sphere.triangles.push_back({0, at(1, j), at(1, j + 1)});
    for (int i = 1; i + 1 < rings; ++i) {
      sphere.triangles.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
      sphere.triangles.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
    }
    sphere.triangles.push_back({at(rings - 1, j), south, at(rings - 1, j + 1)});
  }
  EXPECT_EQ(find_surface_features(sphere, MeshSurface(sphere), o).crease_edges, 0);
}

}  // namespace
