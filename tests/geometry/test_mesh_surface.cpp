#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <random>
#include <set>
#include <string>
#include <vector>

#include "band/band.hpp"
#include "core/error.hpp"
#include "geometry/mesh_surface.hpp"
#include "io/mesh_io.hpp"
#include "test_meshes.hpp"

using namespace poreshell;
namespace fs = std::filesystem;
using poreshell::test_support::icosphere;

namespace {

// ---------- meshes ----------

// Open, curved sheet z = f(x, y) over [lo, hi]^2.
TriangleMesh bumpy_sheet(int n, double lo, double hi) {
  TriangleMesh m;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      const double x = lo + (hi - lo) * i / n, y = lo + (hi - lo) * j / n;
      m.vertices.emplace_back(x, y, 0.5 + 0.05 * std::sin(9 * x) * std::cos(7 * y));
    }
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const int a = j * (n + 1) + i, b = a + 1, c = a + n + 1, d = c + 1;
      m.triangles.push_back({a, b, d});
      m.triangles.push_back({a, d, c});
    }
  return m;
}

// Icosphere with a cap of triangles removed: a scan with a hole.
TriangleMesh holed_sphere() {
  TriangleMesh m = icosphere(2, Vec3(0.1, -0.2, 0.3), 0.7);
  std::erase_if(m.triangles, [&](const auto& t) {
    return (m.vertices[t[0]] + m.vertices[t[1]] + m.vertices[t[2]]).z() / 3 > 0.3 + 0.45;
  });
  return m;
}

// ---------- independent reference: plane projection if inside, else nearest edge ----------

Vec3 ref_segment(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 ab = b - a;
  const double l2 = ab.squaredNorm();
  if (l2 == 0) return a;
  return a + std::clamp((p - a).dot(ab) / l2, 0.0, 1.0) * ab;
}

Vec3 ref_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 n = (b - a).cross(c - a);
  const double longest2 = std::max({(b - a).squaredNorm(), (c - b).squaredNorm(), (a - c).squaredNorm()});
  if (n.norm() > 1e-12 * longest2) {  // else collinear up to round-off: the edges are the triangle
    const Vec3 q = p - n * (n.dot(p - a) / n.squaredNorm());
    // Barycentric signs from sub-triangle normals.
    const double u = n.dot((c - b).cross(q - b)), v = n.dot((a - c).cross(q - c)),
                 w = n.dot((b - a).cross(q - a));
    if (u >= 0 && v >= 0 && w >= 0) return q;
  }
  Vec3 best = ref_segment(p, a, b);
  for (const Vec3& q : {ref_segment(p, b, c), ref_segment(p, c, a)})
    if ((q - p).norm() < (best - p).norm()) best = q;
  return best;
}

struct Nearest {
  double distance;
  Vec3 point;
};

Nearest brute_force(const TriangleMesh& m, const Vec3& p) {
  Nearest best{INFINITY, Vec3::Zero()};
  for (const auto& t : m.triangles) {
    const Vec3 q = ref_triangle(p, m.vertices[t[0]], m.vertices[t[1]], m.vertices[t[2]]);
    if ((q - p).norm() < best.distance) best = {(q - p).norm(), q};
  }
  return best;
}

std::vector<Vec3> query_points(const TriangleMesh& m, int count, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1, 1);
  std::uniform_int_distribution<std::size_t> pick(0, m.vertices.size() - 1);
  std::vector<Vec3> points;
  for (int i = 0; i < count; ++i) {
    const Vec3 r(u(rng), u(rng), u(rng));
    if (i % 3 == 0)
      points.push_back(m.vertices[pick(rng)] + 0.02 * r);  // near
    else if (i % 3 == 1)
      points.push_back(2.0 * r);  // around
    else
      points.push_back(50.0 * r);  // far
  }
  return points;
}

void expect_matches_brute_force(const TriangleMesh& m, int count) {
  const MeshSurface surface(m);
  std::mt19937 rng(7);
  for (const Vec3& p : query_points(m, count, rng)) {
    const Nearest ref = brute_force(m, p);
    const double tol = 1e-12 * (1.0 + ref.distance + p.norm());
    const double d = surface.distance(p);
    ASSERT_NEAR(d, ref.distance, tol) << "at " << p.transpose();
    const Vec3 cp = *surface.closest_point(p);
    EXPECT_NEAR((cp - p).norm(), ref.distance, tol);
    EXPECT_LT(brute_force(m, cp).distance, tol) << "closest point is not on the mesh";
  }
}

}  // namespace

// ---------- closest point on one triangle ----------

TEST(ClosestPointOnTriangle, MatchesReferenceOnRegularSliverAndDegenerateTriangles) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1, 1);
  const auto rnd = [&] { return Vec3(u(rng), u(rng), u(rng)); };
  for (int i = 0; i < 20000; ++i) {
    Vec3 a = rnd(), b = rnd(), c = rnd();
    double tol = 1e-13, on_tol = 1e-13;
    switch (i % 5) {
      case 1:  // sliver; the reference's plane normal is only good to ~1e-7 here
        c = a + 0.37 * (b - a) + 1e-9 * rnd();
        tol = 1e-10;
        on_tol = 1e-6;
        break;
      case 2:  // collinear up to round-off
        c = a + 1.7 * (b - a);
        break;
      case 3:
        b = a;
        break;  // repeated vertex
      case 4:
        b = a;
        c = a;
        break;  // a point
      default:
        break;
    }
    const Vec3 p = 2.0 * rnd();
    const Vec3 q = closest_point_on_triangle(p, a, b, c);
    const Vec3 r = ref_triangle(p, a, b, c);
    ASSERT_TRUE(q.allFinite()) << "case " << i % 5;
    EXPECT_NEAR((q - p).norm(), (r - p).norm(), tol) << "case " << i % 5;
    EXPECT_LT((ref_triangle(q, a, b, c) - q).norm(), on_tol) << "result off the triangle, case " << i % 5;
  }
}

// ---------- BVH against brute force ----------

TEST(MeshSurface, ClosedIcosphereMatchesBruteForce) {
  expect_matches_brute_force(icosphere(3, Vec3(0.2, 0.1, -0.3), 0.8), 1500);
}

TEST(MeshSurface, OpenSheetMatchesBruteForce) {
  expect_matches_brute_force(bumpy_sheet(20, -0.5, 0.5), 1500);
}

TEST(MeshSurface, SphereWithHoleMatchesBruteForce) {
  const TriangleMesh m = holed_sphere();
  ASSERT_GT(analyze_topology(m).boundary_edges, 0);
  expect_matches_brute_force(m, 1500);
}

// The one-search query gives bit for bit what distance and closest_point give apart.
TEST(MeshSurface, OneSearchGivesBothAnswersExactly) {
  const MeshSurface surface(holed_sphere());
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.5, 1.5);
  for (int i = 0; i < 500; ++i) {
    const Vec3 p(u(rng), u(rng), u(rng));
    const SurfaceQuery q = surface.distance_and_closest_point(p);
    ASSERT_EQ(q.distance, surface.distance(p));
    ASSERT_TRUE(q.closest_point);
    ASSERT_EQ(*q.closest_point, *surface.closest_point(p));
  }
}

// The bounded search gives the exact distance within its bound and only says "beyond" past it, never a
// value at or under the bound there: the band scan skips blocks on it.
TEST(MeshSurface, BoundedDistanceIsExactWithinTheBoundAndAboveItBeyond) {
  const MeshSurface surface(holed_sphere());
  std::mt19937 rng(12);
  std::uniform_real_distribution<double> u(-1.5, 1.5), b(0.0, 0.6);
  int within = 0, beyond = 0;
  for (int i = 0; i < 2000; ++i) {
    const Vec3 p(u(rng), u(rng), u(rng));
    const double bound = b(rng), exact = surface.distance(p);
    const double d = surface.distance_up_to(p, bound);
    if (exact <= bound) {
      ASSERT_EQ(d, exact) << i;
      ++within;
    } else {
      ASSERT_GT(d, bound) << i;
      ++beyond;
    }
  }
  EXPECT_GT(within, 100);
  EXPECT_GT(beyond, 100);
}

// A hint on the surface bounds the search and leaves the answer: the closest point of a neighbouring
// query (as the band's scan gives it), a far point of the surface, and a hint off the surface nearer
// than the surface itself (a caller's mistake: the search then starts over unbounded).
TEST(MeshSurface, AHintedQueryFindsTheSameNearestPoint) {
  const MeshSurface surface(holed_sphere());
  std::mt19937 rng(14);
  std::uniform_real_distribution<double> u(-1.5, 1.5), step(-0.05, 0.05);
  for (int i = 0; i < 2000; ++i) {
    const Vec3 p(u(rng), u(rng), u(rng));
    const SurfaceQuery exact = surface.distance_and_closest_point(p);
    const Vec3 neighbour = p + Vec3(step(rng), step(rng), step(rng));
    const Vec3 hints[] = {*surface.closest_point(neighbour), *surface.closest_point(-p),
                          p + 0.5 * (*exact.closest_point - p)};
    for (const Vec3& hint : hints) {
      const SurfaceQuery hinted = surface.distance_and_closest_point_near(p, hint);
      ASSERT_EQ(hinted.distance, exact.distance) << i;
      ASSERT_LT((*hinted.closest_point - *exact.closest_point).norm(), 1e-12) << i;
    }
  }
}

// nearest_triangle names a triangle of the input mesh (not of the tree's leaf order), never one that is
// skipped for a repeated vertex, and gives closest_point's point.
TEST(MeshSurface, NearestTriangleIndexesTheInputTriangles) {
  const TriangleMesh reference = holed_sphere();
  TriangleMesh m = reference;
  // Skipped triangles shift the input indices of those after them.
  m.triangles.insert(m.triangles.begin(), {0, 0, 1});
  m.triangles.insert(m.triangles.begin() + 40, {3, 9, 3});
  const MeshSurface surface(m);
  std::mt19937 rng(13);
  for (const Vec3& p : query_points(m, 600, rng)) {
    const MeshSurface::NearestTriangle nearest = surface.nearest_triangle(p);
    ASSERT_LT(nearest.triangle, m.triangles.size());
    const auto& t = m.triangles[nearest.triangle];
    ASSERT_TRUE(t[0] != t[1] && t[1] != t[2] && t[0] != t[2]) << "a skipped triangle, at " << p.transpose();
    EXPECT_EQ(nearest.point, *surface.closest_point(p));
    const double tol = 1e-12 * (1.0 + p.norm());
    const Vec3 on_it = ref_triangle(p, m.vertices[t[0]], m.vertices[t[1]], m.vertices[t[2]]);
    EXPECT_NEAR((on_it - p).norm(), brute_force(reference, p).distance, tol) << "not the nearest triangle";
    EXPECT_LT((on_it - nearest.point).norm(), tol) << "the point is not on that triangle";
  }
}

TEST(MeshSurface, DistanceIsOneLipschitz) {
  const MeshSurface s(holed_sphere());
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.5, 1.5), small(-1e-3, 1e-3);
  for (int i = 0; i < 20000; ++i) {
    const Vec3 p(u(rng), u(rng), u(rng));
    const Vec3 q = i % 2 ? Vec3(u(rng), u(rng), u(rng)) : Vec3(p + Vec3(small(rng), small(rng), small(rng)));
    ASSERT_LE(std::abs(s.distance(p) - s.distance(q)), (p - q).norm() * (1 + 1e-12) + 1e-15);
  }
}

TEST(MeshSurface, NameBoundsAndErrors) {
  const TriangleMesh m = bumpy_sheet(4, 0.2, 0.8);
  const MeshSurface s(m);
  EXPECT_EQ(s.name(), "mesh");
  EXPECT_NEAR(s.bounds().min.x(), 0.2, 1e-15);
  EXPECT_NEAR(s.bounds().max.y(), 0.8, 1e-15);
  EXPECT_DOUBLE_EQ(s.distance(Vec3(0.5, 0.5, 2.0)), 2.0 - m.vertices[12].z());
  EXPECT_THROW(MeshSurface(TriangleMesh{}), InputError);
  TriangleMesh nan = m;
  nan.vertices[3].x() = NAN;
  EXPECT_THROW(MeshSurface{nan}, InputError);
}

// ---------- band from a mesh ----------

TEST(MeshSurface, IcosphereBandMatchesAnalyticSphereBand) {
  const Vec3 center = Vec3::Constant(0.5);
  const TriangleMesh m = icosphere(4, center, 0.3);
  ASSERT_EQ(m.triangles.size(), 5120u);
  const MeshSurface mesh(m);
  const Sphere sphere(center, 0.3);
  const int n = 33;
  const Grid grid(Vec3::Zero(), 1.0 / (n - 1), {n, n, n});
  const NarrowBand mesh_band = build_band(mesh, grid);
  const NarrowBand sphere_band = build_band(sphere, grid);
  const double delta = BandOptions{}.delta_in_h * grid.h();
  for (const Coord& c : mesh_band.voxels())
    ASSERT_LT(std::abs(sphere.distance(grid.position(c))), delta + grid.h());
  for (const Coord& c : sphere_band.voxels()) ASSERT_LT(mesh.distance(grid.position(c)), delta + grid.h());
  const double ratio = static_cast<double>(mesh_band.size()) / static_cast<double>(sphere_band.size());
  EXPECT_NEAR(ratio, 1.0, 0.05) << mesh_band.size() << " vs " << sphere_band.size();
}

TEST(MeshSurface, OpenSheetGivesABand) {
  const MeshSurface sheet(bumpy_sheet(16, 0.25, 0.75));
  const int n = 33;
  const Grid grid(Vec3::Zero(), 1.0 / (n - 1), {n, n, n});
  const NarrowBand band = build_band(sheet, grid);
  EXPECT_GT(band.size(), 1000u);
  const double delta = BandOptions{}.delta_in_h * grid.h();
  for (std::size_t v = 0; v < band.size(); ++v) ASSERT_LT(band.distance()[v], delta * std::sqrt(3.0));
}

// ---------- the real scan ----------

TEST(MeshIO, StanfordBunnyScan) {
  const fs::path path = fs::path(PORESHELL_DATA_DIR) / "stanford-bunny.obj";
  MeshInputStats stats;
  const TriangleMesh m = read_triangle_mesh(path, &stats);
  std::cout << "  bunny: " << stats.vertices << " vertices, " << stats.triangles << " triangles, "
            << stats.dropped_degenerate << " dropped, " << stats.boundary_edges << " boundary edges\n";
  // The file lists 35947 vertices, but 1113 of them are used by no triangle and are removed.
  EXPECT_EQ(stats.vertices, 34834);
  EXPECT_EQ(stats.triangles + stats.dropped_degenerate, 69451);
  EXPECT_EQ(stats.boundary_edges, 223);

  const MeshSurface surface(m);
  std::mt19937 rng(5);
  const Box box = surface.bounds();
  const Vec3 size = box.max - box.min;
  std::uniform_real_distribution<double> u(-0.25, 1.25);
  std::uniform_int_distribution<std::size_t> pick(0, m.vertices.size() - 1);
  std::vector<Vec3> points;  // half near the scan, half anywhere around it
  for (int i = 0; i < 200; ++i)
    points.push_back(i % 2 ? Vec3(m.vertices[pick(rng)] + 0.02 * size.norm() * Vec3::Random())
                           : Vec3(box.min + Vec3(u(rng), u(rng), u(rng)).cwiseProduct(size)));
  for (std::size_t i = 0; i < points.size(); ++i)
    ASSERT_NEAR(surface.distance(points[i]), brute_force(m, points[i]).distance, 1e-12);
}
