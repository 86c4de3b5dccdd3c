// Isosurface extraction: topology of thin shells (spheres, pores, tori), random fields with
// ambiguous and exactly-at-iso values, determinism across thread counts, world coordinates.

#include <gtest/gtest.h>

#include <tbb/global_control.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <numbers>
#include <random>

#include "core/error.hpp"
#include "geometry/isosurface.hpp"

namespace poreshell {
namespace {

struct Field {
  Grid grid;
  std::vector<Coord> points;
  std::vector<double> values;
  SparseField view(double background = 1.0) const { return {&grid, points, values, background}; }
};

// A thin shell around the surface {distance(x) = 0} as the pipeline produces it: -1 within 1.5h
// of the surface, rising to +1 at 2.5h; points are kept only where |distance| < 3h.
Field shell_field(int n, const std::function<double(const Vec3&)>& distance) {
  Field f{Grid(Vec3(0, 0, 0), 1.0, {n, n, n}), {}, {}};
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const Coord c{i, j, k};
        const double d = std::abs(distance(f.grid.position(c)));
        if (d >= 3.0) continue;
        f.points.push_back(c);
        f.values.push_back(std::clamp(d - 1.5, -1.0, 1.0));
      }
  return f;
}

Field sphere_shell(int n, double radius) {
  const Vec3 center = Vec3::Constant((n - 1) / 2.0);
  return shell_field(n, [=](const Vec3& p) { return (p - center).norm() - radius; });
}

void expect_valid(const MeshTopology& t) {
  EXPECT_GT(t.triangles, 0);
  EXPECT_TRUE(t.closed()) << t.boundary_edges << " boundary edges";
  EXPECT_EQ(t.nonmanifold_edges, 0);
  EXPECT_EQ(t.nonmanifold_vertices, 0);
  EXPECT_EQ(t.misoriented_edges, 0);
  EXPECT_EQ(t.degenerate_triangles, 0);
  EXPECT_GT(t.signed_volume, 0.0);
}

TEST(Isosurface, SphereShellIsTwoSpheres) {
  const double radius = 12.0;
  const Field f = sphere_shell(33, radius);
  for (double iso : {-0.3, 0.0, 0.3}) {
    SCOPED_TRACE(iso);
    const MeshTopology t = analyze_topology(extract_isosurface(f.view(), iso));
    expect_valid(t);
    EXPECT_EQ(t.components, 2);
    EXPECT_EQ(t.euler_characteristic, 4);
    const double thickness = 2 * (1.5 + iso);  // where the clamped ramp crosses iso
    const double expected = 4 * std::numbers::pi * radius * radius * thickness;
    EXPECT_NEAR(t.signed_volume, expected, 0.15 * expected);
  }
}

TEST(Isosurface, NoSliversWhereTheSurfacePassesNearGridPoints) {
  // Sphere shells at radii whose surface grazes many grid points: crossings next to a grid point are
  // kept a twentieth of an edge away from it, so no triangle gets an angle under 1 degree.
  for (double radius : {10.0, 10.5, 11.0, 12.0, 12.25}) {
    SCOPED_TRACE(radius);
    const Field f = sphere_shell(33, radius);
    const MeshTopology t = analyze_topology(extract_isosurface(f.view(), 0.0));
    expect_valid(t);
    EXPECT_GT(t.min_angle_degrees, 1.0);
  }
}

TEST(Isosurface, ClampedCrossingsStayOnAFlatFace) {
  // A tilted plane through a linear field, offset so that it grazes many grid points. Crossings clamped
  // away from a grid point go onto the plane, not along their edge off it (where they stood up to 0.05
  // of an edge off the face, bumps a 0.02 mm reduction had to keep); only those that would make a
  // triangle under the least angle go back.
  const Vec3 normal = Vec3(0.3, 0.5, 0.81).normalized();
  const int n = 24;
  for (double offset : {11.0, 11.37, 12.02}) {
    SCOPED_TRACE(offset);
    Field f{Grid(Vec3(0, 0, 0), 1.0, {n, n, n}), {}, {}};
    for (int k = 0; k < n; ++k)
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
          const double d = normal.dot(Vec3(i, j, k)) - offset;
          if (std::abs(d) >= 4.0) continue;
          f.points.push_back({i, j, k});
          f.values.push_back(d / 4.0);
        }
    const TriangleMesh mesh = extract_isosurface(f.view(), 0.0);
    const MeshTopology t = analyze_topology(mesh);
    expect_valid(t);
    EXPECT_GT(t.min_angle_degrees, 1.0);
    int on_face = 0, off = 0;
    double farthest = 0.0;
    for (const Vec3& v : mesh.vertices) {
      const double d = std::abs(normal.dot(v) - offset);
      // The band's own end and the grid's sides, where the plane is cut off, are not the face.
      if (d > 0.1 || v.minCoeff() < 1.0 || v.maxCoeff() > n - 2.0) continue;
      ++on_face;
      if (d > 1e-9) ++off;
      farthest = std::max(farthest, d);
    }
    std::printf("offset %.2f: %d of %d face vertices off the face, the farthest %.4f edges\n", offset, off,
                on_face, farthest);
    EXPECT_GT(on_face, 500);
    EXPECT_LT(off, 0.01 * on_face);
  }
}

TEST(Isosurface, EachPoreThroughTheShellLowersEulerByTwo) {
  const int n = 33;
  const Vec3 center = Vec3::Constant((n - 1) / 2.0);
  const Vec3 axes[6] = {Vec3::UnitX(),  -Vec3::UnitX(), Vec3::UnitY(),
                        -Vec3::UnitY(), Vec3::UnitZ(),  -Vec3::UnitZ()};
  for (int pores : {1, 2, 3, 6}) {
    SCOPED_TRACE(pores);
    Field f = sphere_shell(n, 12.0);
    for (std::size_t p = 0; p < f.points.size(); ++p) {
      const Vec3 dir = (f.grid.position(f.points[p]) - center).normalized();
      for (int a = 0; a < pores; ++a)
        if ((dir - axes[a]).norm() < 0.3) f.values[p] = 1.0;  // a disk of radius ~3.6h
    }
    for (double iso : {-0.3, 0.0, 0.3}) {
      const MeshTopology t = analyze_topology(extract_isosurface(f.view(), iso));
      expect_valid(t);
      EXPECT_EQ(t.components, 1);
      EXPECT_EQ(t.euler_characteristic, 4 - 2 * pores) << "iso " << iso;
      EXPECT_EQ(isosurface_euler_characteristic(f.view(), iso), 4 - 2 * pores) << "iso " << iso;
    }
  }
}

// A slab cut by a cylinder (a pore through a wall): the solid {max(a, b) < 0}, a = |z - c| - t/2 the
// slab, b = r - |xy| the pore, meets at a sharp rim. Meshed from the max alone, vertices near the rim are
// interpolated from the crease and lie up to a third of a cell off the solid's true boundary; from its
// two parts each lies on it but for the crossing clamp (0.05 of an edge) and the cylinder's curvature
// along an edge. Triangles from vertices on the two parts' faces cut the rim's corner unless the crease
// points are vertices too (tet_creases.hpp): measured at the triangles' centroids and edge midpoints.
TEST(Isosurface, MaxOfTwoPartsKeepsTheSharpEdgeWhereTheyMeet) {
  const int n = 24;
  const Vec3 axis(11.3, 11.6, 0.0);
  const double centre = 11.4, half = 3.3, radius = 5.2;
  const auto part_a = [&](const Vec3& p) { return std::abs(p.z() - centre) - half; };
  const auto part_b = [&](const Vec3& p) {
    return radius - Vec3(p.x() - axis.x(), p.y() - axis.y(), 0).norm();
  };
  Field f{Grid(Vec3(0, 0, 0), 1.0, {n, n, n}), {}, {}};
  std::vector<double> a, b;
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const Coord c{i, j, k};
        const Vec3 p = f.grid.position(c);
        if (i == 0 || j == 0 || k == 0 || i == n - 1 || j == n - 1 || k == n - 1) continue;  // background
        f.points.push_back(c);
        a.push_back(part_a(p));
        b.push_back(
            std::max(part_b(p), std::max(std::abs(p.x() - axis.x()), std::abs(p.y() - axis.y())) - 8.0));
        f.values.push_back(std::max(a.back(), b.back()));
      }
  // b also closes the slab 8 cells from the axis (a square frame, whose own edges are a max within b),
  // so the solid is bounded; measured around the pore only.
  const auto off = [&](const Vec3& x) { return std::abs(std::max(part_a(x), part_b(x))); };
  const auto worst_vertex = [&](const TriangleMesh& mesh) {
    double worst = 0.0;
    for (const Vec3& v : mesh.vertices)
      if (part_b(v) > -1.5) worst = std::max(worst, off(v));
    return worst;
  };
  // The 95th percentile of the rim's triangles' centroids' and edge midpoints' distances.
  const auto cut = [&](const TriangleMesh& mesh) {
    std::vector<double> d;
    for (const Triangle& t : mesh.triangles) {
      const Vec3 &p = mesh.vertices[t[0]], &q = mesh.vertices[t[1]], &r = mesh.vertices[t[2]];
      for (const Vec3& x : {Vec3((p + q + r) / 3.0), Vec3((p + q) / 2), Vec3((q + r) / 2), Vec3((r + p) / 2)})
        if (part_b(x) > -1.5) d.push_back(off(x));
    }
    std::sort(d.begin(), d.end());
    return d[d.size() * 95 / 100];
  };
  const TriangleMesh from_max = extract_isosurface(f.view(), 0.0);
  SparseField parts = f.view();
  const std::vector<std::span<const double>> both{a, b};
  parts.parts = both;
  parts.sharp_creases = false;
  const TriangleMesh chamfered = extract_isosurface(parts, 0.0);
  parts.sharp_creases = true;
  const TriangleMesh sharp = extract_isosurface(parts, 0.0);
  const MeshTopology max_topology = analyze_topology(from_max), sharp_topology = analyze_topology(sharp);
  expect_valid(analyze_topology(chamfered));
  expect_valid(sharp_topology);
  EXPECT_EQ(chamfered.triangles.size(), from_max.triangles.size());  // the same cells, moved vertices
  EXPECT_EQ(sharp_topology.euler_characteristic, max_topology.euler_characteristic);
  EXPECT_GT(sharp_topology.min_angle_degrees, 1.0);
  std::printf(
      "farthest vertex off the solid's boundary, cells: %.4f from the max, %.4f from its parts, %.4f "
      "with crease points\n",
      worst_vertex(from_max), worst_vertex(chamfered), worst_vertex(sharp));
  std::printf(
      "95th percentile of the rim's centroids and edge midpoints: %.4f, %.4f, %.4f cells; %zu, %zu "
      "triangles; smallest angle %.2f, %.2f degrees\n",
      cut(from_max), cut(chamfered), cut(sharp), chamfered.triangles.size(), sharp.triangles.size(),
      max_topology.min_angle_degrees, sharp_topology.min_angle_degrees);
  EXPECT_GT(worst_vertex(from_max), 0.25);
  EXPECT_LT(worst_vertex(chamfered), 0.1);
  EXPECT_LT(worst_vertex(sharp), 0.1);
  EXPECT_GT(cut(chamfered), 0.1);
  EXPECT_LT(cut(sharp), 0.06);
}

TEST(Isosurface, TorusShellIsTwoTori) {
  const int n = 41;
  const Vec3 center = Vec3::Constant((n - 1) / 2.0);
  const Field f = shell_field(n, [=](const Vec3& p) {
    const Vec3 q = p - center;
    return std::hypot(std::hypot(q.x(), q.y()) - 11.0, q.z()) - 5.0;
  });
  const MeshTopology t = analyze_topology(extract_isosurface(f.view(), 0.0));
  expect_valid(t);
  EXPECT_EQ(t.components, 2);
  EXPECT_EQ(t.euler_characteristic, 0);
  EXPECT_EQ(isosurface_euler_characteristic(f.view(), 0.0), 0);
}

// Euler characteristic of the solid {value < iso}, computed independently of the mesh: the
// solid retracts onto the Kuhn simplices whose vertices are all inside, so chi(solid) is their
// alternating count, and the boundary of a 3-manifold has chi = 2 chi(solid).
std::int64_t solid_euler(const Field& f, double iso, int n) {
  auto inside = [&](int i, int j, int k) {
    if (i < 0 || j < 0 || k < 0 || i >= n || j >= n || k >= n) return false;
    return f.values[i + n * (j + n * k)] < iso;
  };
  auto in = [&](const Coord& p, int bits) {
    return inside(p.i + (bits & 1), p.j + (bits >> 1 & 1), p.k + (bits >> 2));
  };
  std::int64_t chi = 0;
  for (const Coord& p : f.points) {
    if (!in(p, 0)) continue;
    chi += 1;
    for (int d = 1; d < 8; ++d) chi -= in(p, d);  // edges p -> p + d
    for (int d1 = 1; d1 < 8; ++d1)                // triangles p, p + d1, p + d1 + d2
      for (int d2 = 1; d2 < 8; ++d2)
        if ((d1 & d2) == 0) chi += in(p, d1) && in(p, d1 | d2);
    for (int a : {1, 2, 4})  // tetrahedra p, +a, +a+b, +111
      for (int b : {1, 2, 4})
        if (a != b) chi -= in(p, a) && in(p, a | b) && in(p, 7);
  }
  return 2 * chi;
}

TEST(Isosurface, RandomFieldsGiveClosedManifoldsWithTheRightEuler) {
  const int n = 8;
  for (unsigned seed = 1; seed <= 30; ++seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> uniform(-1.0, 1.0);
    std::uniform_int_distribution<int> level(0, 4);
    const double quantized[5] = {-1.0, -0.3, 0.0, 0.3, 1.0};  // many values exactly at an iso level
    Field f{Grid(Vec3(0, 0, 0), 1.0, {n, n, n}), {}, {}};
    for (int k = 0; k < n; ++k)
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
          f.points.push_back({i, j, k});
          f.values.push_back(seed % 2 ? uniform(rng) : quantized[level(rng)]);
        }
    for (double iso : {-0.3, 0.0, 0.3}) {
      SCOPED_TRACE(testing::Message() << "seed " << seed << " iso " << iso);
      const MeshTopology t = analyze_topology(extract_isosurface(f.view(), iso));
      expect_valid(t);
      EXPECT_EQ(t.euler_characteristic, solid_euler(f, iso, n));
      EXPECT_EQ(isosurface_euler_characteristic(f.view(), iso), t.euler_characteristic);
    }
  }
}

// Crease points split the marching tetrahedra's patches, made alike by the tetrahedra on either side of
// a face, so the surface of random parts (two or three, some grid points not sampled, values at the level)
// stays closed and manifold with the same topology as the max's alone (2,000 fields passed).
TEST(Isosurface, RandomPartsGiveClosedManifoldsWithCreasePoints) {
  const int n = 9;
  std::int64_t crease_vertices = 0;
  for (unsigned seed = 1; seed <= 40; ++seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> uniform(-1.0, 1.0);
    std::bernoulli_distribution dropped(0.05), at_level(0.05);
    const std::size_t part_count = 2 + seed % 2;
    Field f{Grid(Vec3(0, 0, 0), 1.0, {n, n, n}), {}, {}};
    std::vector<std::vector<double>> part_values(part_count);
    // Each part a gentle slope plus noise, so that the solid has faces and creases, not only specks.
    std::vector<Vec3> slope(part_count);
    for (Vec3& g : slope) g = Vec3(uniform(rng), uniform(rng), uniform(rng)) * 0.4;
    for (int k = 0; k < n; ++k)
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
          if (dropped(rng)) continue;
          const Vec3 p = f.grid.position({i, j, k}) - Vec3::Constant((n - 1) / 2.0);
          f.points.push_back({i, j, k});
          double value = -1.0;
          for (std::size_t q = 0; q < part_count; ++q) {
            part_values[q].push_back(at_level(rng) ? 0.0 : slope[q].dot(p) + 0.6 * uniform(rng) - 0.3);
            value = std::max(value, part_values[q].back());
          }
          f.values.push_back(value);
        }
    SparseField parts = f.view();
    std::vector<std::span<const double>> spans(part_values.begin(), part_values.end());
    parts.parts = spans;
    SCOPED_TRACE(testing::Message() << "seed " << seed << ", " << part_count << " parts");
    const TriangleMesh sharp = extract_isosurface(parts, 0.0);
    parts.sharp_creases = false;
    const TriangleMesh chamfered = extract_isosurface(parts, 0.0);
    const MeshTopology t = analyze_topology(sharp);
    expect_valid(t);
    EXPECT_EQ(t.euler_characteristic, isosurface_euler_characteristic(f.view(), 0.0));
    // A piece of one vertex between two crease points nearly in line with them is a sliver: 2 of 2,000
    // such fields had an angle under 1 degree (0.60 and 0.61), the chamfered meshes none under 1.45.
    EXPECT_GT(t.min_angle_degrees, 0.5);
    crease_vertices += static_cast<std::int64_t>(sharp.vertices.size() - chamfered.vertices.size());
  }
  std::printf("%lld crease vertices in 40 fields\n", static_cast<long long>(crease_vertices));
  EXPECT_GT(crease_vertices, 1000);
}

TEST(Isosurface, SameBytesForAnyThreadCount) {
  Field f = sphere_shell(45, 18.0);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> noise(-0.5, 0.5);
  for (double& v : f.values) v = std::clamp(v + noise(rng), -1.0, 1.0);
  auto run = [&](int threads) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    return extract_isosurface(f.view(), 0.0);
  };
  const TriangleMesh one = run(1), two = run(2);
  ASSERT_GT(one.triangles.size(), 10000u);  // enough cells for several parallel chunks
  EXPECT_EQ(one.triangles, two.triangles);
  ASSERT_EQ(one.vertices.size(), two.vertices.size());
  for (std::size_t v = 0; v < one.vertices.size(); ++v) ASSERT_EQ(one.vertices[v], two.vertices[v]) << v;
}

// Points in key order are read as they are, others through a sorted copy: the same mesh either way.
TEST(Isosurface, SameMeshForPointsInAnyOrder) {
  const Field sorted = sphere_shell(29, 10.0);  // made in key order
  Field shuffled = sorted;
  std::vector<std::size_t> order(sorted.points.size());
  for (std::size_t n = 0; n < order.size(); ++n) order[n] = n;
  std::shuffle(order.begin(), order.end(), std::mt19937(3));
  for (std::size_t n = 0; n < order.size(); ++n) {
    shuffled.points[n] = sorted.points[order[n]];
    shuffled.values[n] = sorted.values[order[n]];
  }
  const TriangleMesh a = extract_isosurface(sorted.view(), 0.0), b = extract_isosurface(shuffled.view(), 0.0);
  ASSERT_GT(a.triangles.size(), 1000u);
  EXPECT_EQ(a.triangles, b.triangles);
  EXPECT_EQ(a.vertices, b.vertices);
  // A point given twice is refused on both paths.
  for (Field twice : {sorted, shuffled}) {
    twice.points.insert(twice.points.begin() + 5, twice.points[5]);
    twice.values.insert(twice.values.begin() + 5, twice.values[5]);
    EXPECT_THROW(extract_isosurface(twice.view(), 0.0), std::invalid_argument);
  }
}

TEST(Isosurface, VerticesAreInWorldCoordinates) {
  const Vec3 origin(-2.5, 1.25, 10.0);
  const double h = 0.37;
  Field f{Grid(origin, h, {17, 23, 31}), {}, {}};
  // A box of inside points (i in [0, 10] touches the grid's low x face), ringed by outside ones.
  for (int k = 4; k <= 21; ++k)
    for (int j = 3; j <= 16; ++j)
      for (int i = 0; i <= 11; ++i) {
        const bool in = i <= 10 && j >= 4 && j <= 15 && k >= 5 && k <= 20;
        f.points.push_back({i, j, k});
        f.values.push_back(in ? -1.0 : 1.0);
      }
  const TriangleMesh mesh = extract_isosurface(f.view(), 0.0);
  const MeshTopology t = analyze_topology(mesh);
  expect_valid(t);
  EXPECT_EQ(t.euler_characteristic, 2);
  Vec3 lo = Vec3::Constant(1e300), hi = Vec3::Constant(-1e300);
  for (const Vec3& v : mesh.vertices) {
    lo = lo.cwiseMin(v);
    hi = hi.cwiseMax(v);
  }
  // Crossings sit halfway between the last inside and first outside point.
  const Vec3 want_lo = origin + h * Vec3(-0.5, 3.5, 4.5), want_hi = origin + h * Vec3(10.5, 15.5, 20.5);
  EXPECT_LT((lo - want_lo).norm(), 1e-9) << lo.transpose();
  EXPECT_LT((hi - want_hi).norm(), 1e-9) << hi.transpose();
  const double box = (want_hi - want_lo).prod();
  EXPECT_NEAR(t.signed_volume, box, 0.1 * box);
}

TEST(Isosurface, EmptySolidAndBadIsoLevel) {
  Field f{Grid(Vec3(0, 0, 0), 1.0, {4, 4, 4}), {{1, 1, 1}}, {0.5}};
  EXPECT_TRUE(extract_isosurface(f.view(), 0.0).triangles.empty());
  EXPECT_THROW(extract_isosurface(f.view(1.0), 1.0), InputError);
}

TEST(Isosurface, LargeSphereShellTiming) {
  const Field f = sphere_shell(111, 51.0);
  const auto start = std::chrono::steady_clock::now();
  const TriangleMesh mesh = extract_isosurface(f.view(), 0.0);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::cout << f.points.size() << " points -> " << mesh.triangles.size() << " triangles in " << seconds
            << " s\n";
  const MeshTopology t = analyze_topology(mesh);
  expect_valid(t);
  EXPECT_EQ(t.euler_characteristic, 4);
}

}  // namespace
}  // namespace poreshell
