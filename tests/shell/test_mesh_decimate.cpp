// Triangle reduction: what a printable mesh must keep (closed, manifold, oriented, genus, volume),
// the distance bound measured both ways, triangle shapes, determinism, and the cases left alone.

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <Eigen/Geometry>  // cross()
#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <numbers>
#include <set>
#include <stdexcept>
#include <utility>

#include "core/error.hpp"
#include "deviation_probe.hpp"
#include "geometry/isosurface.hpp"
#include "geometry/mesh_surface.hpp"
#include "reduce/collapse_bounds.hpp"
#include "reduce/mesh_decimate.hpp"

namespace poreshell {
namespace {

// Parametric torus around the z axis, outward oriented: n segments around the axis, m around the tube.
TriangleMesh torus(int n, int m, double big_radius, double small_radius) {
  TriangleMesh mesh;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < m; ++j) {
      const double u = 2 * std::numbers::pi * i / n, v = 2 * std::numbers::pi * j / m;
      const double rho = big_radius + small_radius * std::cos(v);
      mesh.vertices.emplace_back(rho * std::cos(u), rho * std::sin(u), small_radius * std::sin(v));
    }
  auto id = [&](int i, int j) { return static_cast<std::int32_t>((i % n) * m + (j % m)); };
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < m; ++j) {
      mesh.triangles.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      mesh.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  return mesh;
}

// Axis-aligned cube [0, 1]^3 with every face split into n x n squares: large flat regions.
TriangleMesh tessellated_cube(int n) {
  TriangleMesh mesh;
  std::map<std::array<int, 3>, std::int32_t> index;  // lattice point -> vertex
  auto vertex = [&](std::array<int, 3> c) {
    const auto [it, added] = index.try_emplace(c, static_cast<std::int32_t>(mesh.vertices.size()));
    if (added) mesh.vertices.emplace_back(c[0] / double(n), c[1] / double(n), c[2] / double(n));
    return it->second;
  };
  for (int axis = 0; axis < 3; ++axis)
    for (int side = 0; side < 2; ++side) {
      const int u = (axis + 1) % 3, v = (axis + 2) % 3;  // (u, v, axis) is right-handed
      for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
          std::array<std::array<int, 3>, 4> q;  // corners counter-clockwise in (u, v)
          const int di[4] = {0, 1, 1, 0}, dj[4] = {0, 0, 1, 1};
          for (int k = 0; k < 4; ++k) {
            q[k][axis] = side * n;
            q[k][u] = i + di[k];
            q[k][v] = j + dj[k];
          }
          if (side == 0) std::swap(q[1], q[3]);  // the low face looks the other way
          mesh.triangles.push_back({vertex(q[0]), vertex(q[1]), vertex(q[2])});
          mesh.triangles.push_back({vertex(q[0]), vertex(q[2]), vertex(q[3])});
        }
    }
  return mesh;
}

// A marching-tetrahedra mesh as the pipeline writes them, slivers included: a spherical shell of
// radius 12 and thickness 3 (grid units) with `pores` holes of radius about 3.6 through it, along
// the axes.
TriangleMesh porous_shell(int pores) {
  const int n = 33;
  const Grid grid(Vec3::Zero(), 1.0, {n, n, n});
  const Vec3 center = Vec3::Constant((n - 1) / 2.0);
  const Vec3 axes[6] = {Vec3::UnitX(),  Vec3::UnitY(),  Vec3::UnitZ(),
                        -Vec3::UnitX(), -Vec3::UnitY(), -Vec3::UnitZ()};
  std::vector<Coord> points;
  std::vector<double> values;
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const Coord c{i, j, k};
        const Vec3 d = grid.position(c) - center;
        const double distance = std::abs(d.norm() - 12.0);
        if (distance >= 3.0) continue;
        double value = std::clamp(distance - 1.5, -1.0, 1.0);
        for (int a = 0; a < pores; ++a)
          if ((d.normalized() - axes[a]).norm() < 0.3) value = 1.0;
        points.push_back(c);
        values.push_back(value);
      }
  return extract_isosurface({&grid, points, values, 1.0}, 0.0);
}

double area(const TriangleMesh& mesh) {
  double sum = 0.0;
  for (const auto& t : mesh.triangles) {
    const Vec3& a = mesh.vertices[t[0]];
    sum += 0.5 * (mesh.vertices[t[1]] - a).cross(mesh.vertices[t[2]] - a).norm();
  }
  return sum;
}

double min_angle_degrees(const TriangleMesh& mesh, const std::array<std::int32_t, 3>& t) {
  double least = 180.0;
  for (int i = 0; i < 3; ++i) {
    const Vec3 a = mesh.vertices[t[(i + 1) % 3]] - mesh.vertices[t[i]];
    const Vec3 b = mesh.vertices[t[(i + 2) % 3]] - mesh.vertices[t[i]];
    least = std::min(least, std::atan2(a.cross(b).norm(), a.dot(b)) * 180.0 / std::numbers::pi);
  }
  return least;
}

double min_angle_degrees(const TriangleMesh& mesh) {
  double least = 180.0;
  for (const auto& t : mesh.triangles) least = std::min(least, min_angle_degrees(mesh, t));
  return least;
}

// Largest distance, measured here independently, between the surfaces: from the reduced mesh's
// vertices, centroids and edge midpoints to the original, and from the original vertices to the
// reduced mesh.
double two_sided_distance(const TriangleMesh& original, const TriangleMesh& reduced) {
  const MeshSurface to_original(original), to_reduced(reduced);
  double d = 0.0;
  for (const Vec3& p : reduced.vertices) d = std::max(d, to_original.distance(p));
  for (const auto& t : reduced.triangles) {
    const Vec3 &a = reduced.vertices[t[0]], &b = reduced.vertices[t[1]], &c = reduced.vertices[t[2]];
    for (const Vec3& p :
         {Vec3((a + b + c) / 3.0), Vec3((a + b) / 2.0), Vec3((b + c) / 2.0), Vec3((c + a) / 2.0)})
      d = std::max(d, to_original.distance(p));
  }
  for (const Vec3& p : original.vertices) d = std::max(d, to_reduced.distance(p));
  return d;
}

// Largest distance from points spread over every triangle of `from` (a grid of `steps` + 1 along each
// side, corners included) to the surface `to`.
double largest_distance_over(const TriangleMesh& from, const TriangleMesh& to, int steps) {
  const MeshSurface surface(to);
  double d = 0.0;
  for (const auto& t : from.triangles)
    for (int i = 0; i <= steps; ++i)
      for (int j = 0; i + j <= steps; ++j) {
        const double u = static_cast<double>(i) / steps, v = static_cast<double>(j) / steps;
        const Vec3 p =
            (1.0 - u - v) * from.vertices[t[0]] + u * from.vertices[t[1]] + v * from.vertices[t[2]];
        d = std::max(d, surface.distance(p));
      }
  return d;
}

void expect_printable(const MeshTopology& t) {
  EXPECT_TRUE(t.closed()) << t.boundary_edges << " boundary edges";
  EXPECT_TRUE(t.manifold()) << t.nonmanifold_edges << " edges, " << t.nonmanifold_vertices << " vertices";
  EXPECT_TRUE(t.oriented()) << t.misoriented_edges << " misoriented edges";
  EXPECT_EQ(t.degenerate_triangles, 0);
  EXPECT_GT(t.signed_volume, 0.0);
}

// Checks everything decimate_mesh() promises about `reduced`, made from `original`.
void expect_faithful(const TriangleMesh& original, const TriangleMesh& reduced,
                     const DecimateOptions& options, const DecimateResult& result) {
  const MeshTopology before = analyze_topology(original), after = analyze_topology(reduced);
  expect_printable(after);
  EXPECT_EQ(after.euler_characteristic, before.euler_characteristic);
  EXPECT_EQ(after.components, before.components);
  EXPECT_EQ(result.triangles_before, before.triangles);
  EXPECT_EQ(result.triangles_after, after.triangles);
  EXPECT_EQ(result.reached_target, after.triangles <= options.max_triangles);
  const double distance = two_sided_distance(original, reduced);
  EXPECT_LE(distance, options.max_distance);
  // The result's figure is the larger of the reduction's own points and the sampled check's.
  EXPECT_GE(result.max_distance, distance - 1e-12 * options.max_distance);
  EXPECT_LE(result.max_distance, options.max_distance);
  EXPECT_LE(result.sampled.max(), result.max_distance);
}

DecimateResult decimate(TriangleMesh& mesh, std::int64_t max_triangles, double max_distance) {
  return decimate_mesh(mesh, {max_triangles, max_distance});
}

// Two cones on a ring of n vertices, apexes on the axis: each apex has n triangles around it.
TriangleMesh bipyramid(int n) {
  TriangleMesh mesh;
  for (int i = 0; i < n; ++i) {
    const double a = 2.0 * std::numbers::pi * i / n;
    mesh.vertices.push_back({std::cos(a), std::sin(a), 0.0});
  }
  mesh.vertices.push_back({0.0, 0.0, 1.0});
  mesh.vertices.push_back({0.0, 0.0, -1.0});
  for (int i = 0; i < n; ++i) {
    mesh.triangles.push_back({i, (i + 1) % n, n});
    mesh.triangles.push_back({(i + 1) % n, i, n + 1});
  }
  return mesh;
}

TEST(MeshDecimate, CornerTableJoinsEachEdgesTwoTriangles) {
  // The bipyramid's apexes have more triangles (40) than opposite_corners() keeps on its stack.
  for (const TriangleMesh& mesh : {torus(12, 8, 3.0, 1.0), bipyramid(40)}) {
    const std::vector<std::int32_t> opposite = opposite_corners(mesh);
    ASSERT_EQ(opposite.size(), 3 * mesh.triangles.size());
    const auto vertex = [&](std::int32_t c) {
      return mesh.triangles[static_cast<std::size_t>(c / 3)][c % 3];
    };
    for (std::int32_t c = 0; c < static_cast<std::int32_t>(opposite.size()); ++c) {
      const std::int32_t o = opposite[static_cast<std::size_t>(c)];
      ASSERT_GE(o, 0);
      EXPECT_NE(o / 3, c / 3);
      EXPECT_EQ(opposite[static_cast<std::size_t>(o)], c);
      // c faces u -> w; the corner across faces w -> u (consistent orientation).
      EXPECT_EQ(vertex(next_corner(c)), vertex(previous_corner(o)));
      EXPECT_EQ(vertex(previous_corner(c)), vertex(next_corner(o)));
    }
    // An open mesh has edges with one triangle: refused.
    TriangleMesh open = mesh;
    open.triangles.pop_back();
    EXPECT_THROW(opposite_corners(open), std::runtime_error);
  }
}

// 9600 triangles are reduced by one worker, 24,000 in parts at once (edge_collapse.cpp): either way to
// the target within the bound.
class TorusReduction : public ::testing::TestWithParam<std::array<int, 2>> {};

TEST_P(TorusReduction, ReachesTargetWithinBound) {
  const TriangleMesh original = torus(GetParam()[0], GetParam()[1], 3.0, 1.0);
  TriangleMesh mesh = original;
  const DecimateOptions options{1500, 0.03};
  const DecimateResult result = decimate_mesh(mesh, options);
  EXPECT_TRUE(result.reached_target);
  EXPECT_LE(result.triangles_after, 1500);
  EXPECT_GT(result.triangles_after, 1400);  // stops at the target, not far below
  expect_faithful(original, mesh, options, result);
  EXPECT_EQ(analyze_topology(mesh).euler_characteristic, 0);  // still a torus

  // Every vertex kept is an original one.
  std::set<std::array<double, 3>> original_vertices;
  for (const Vec3& p : original.vertices) original_vertices.insert({p.x(), p.y(), p.z()});
  for (const Vec3& p : mesh.vertices) EXPECT_TRUE(original_vertices.count({p.x(), p.y(), p.z()}));

  // The volume between the surfaces is at most max_distance * area (6 % of the volume here), and
  // chords of a curved surface stand off it by a third to a half of their largest gap on average.
  const double volume = analyze_topology(original).signed_volume;
  EXPECT_NEAR(analyze_topology(mesh).signed_volume, volume, 0.5 * options.max_distance * area(original));
  // No slivers: the new triangles keep angles of 10 degrees (the input has none smaller).
  EXPECT_GE(min_angle_degrees(original), 10.0);
  EXPECT_GE(min_angle_degrees(mesh), 10.0 - 1e-9);
}

INSTANTIATE_TEST_SUITE_P(MeshDecimate, TorusReduction,
                         ::testing::Values(std::array<int, 2>{120, 40}, std::array<int, 2>{200, 60}));

TEST(MeshDecimate, PorousShellKeepsGenusAndMakesNoSlivers) {
  // The case of the demo output: with the removed vertices' distances alone bounded (as OpenMesh's
  // ModHausdorff did), triangles at the pore rims end up 0.35 off the original.
  const TriangleMesh original = porous_shell(6);
  ASSERT_EQ(analyze_topology(original).euler_characteristic, 4 - 2 * 6);
  TriangleMesh mesh = original;
  const DecimateOptions options{static_cast<std::int64_t>(original.triangles.size() / 8), 0.05};
  const DecimateResult result = decimate_mesh(mesh, options);
  // A quarter before the sampled check (issue 49) found the first attempt's rims off the bound.
  EXPECT_LT(result.triangles_after, result.triangles_before / 3);
  expect_faithful(original, mesh, options, result);

  // Marching tetrahedra leave slivers. A new triangle may have an angle below 10 degrees only
  // where it replaces a sharper one, so collapses take most slivers away and make none sharper.
  int slivers_before = 0, slivers_after = 0;
  for (const auto& t : original.triangles) slivers_before += min_angle_degrees(original, t) < 10.0;
  for (const auto& t : mesh.triangles) slivers_after += min_angle_degrees(mesh, t) < 10.0;
  ASSERT_GT(slivers_before, 100);
  EXPECT_LT(slivers_after, slivers_before / 4);
  EXPECT_GE(min_angle_degrees(mesh), min_angle_degrees(original));
}

TEST(MeshDecimate, FanBoundsHoldEverywhereNotOnlyWhereMeasured) {
  // A bound from the fans alone holds at every point of a triangle, not only at the points the checks
  // ask about: with it alone, reducing as far as it allows, the distance measured never overshoots
  // (which would take a second attempt), and dense points on either surface stay within the bound of
  // the other.
  for (const auto& [original, max_distance] :
       {std::pair{torus(60, 20, 3.0, 1.0), 0.05}, std::pair{porous_shell(6), 0.1}}) {
    TriangleMesh mesh = original;
    DecimateOptions options{4, max_distance};
    options.rule = DistanceRule::kBoundOnly;
    const DecimateResult result = decimate_mesh(mesh, options);
    EXPECT_EQ(result.attempts, 1);
    EXPECT_EQ(result.collapses.checked, 0);
    EXPECT_LT(result.triangles_after, 0.6 * static_cast<double>(result.triangles_before));
    expect_faithful(original, mesh, options, result);
    EXPECT_LE(largest_distance_over(mesh, original, 8), options.max_distance);
    EXPECT_LE(largest_distance_over(original, mesh, 3), options.max_distance);
  }
}

// Issue 49: the default output reduces as far as the bound allows, and the result carries a check of
// its own by sampling both surfaces; an independent sampler (deviation_probe.hpp) agrees it is within.
TEST(MeshDecimate, AsFarAsTheBoundAllowsIsWithinItBySampling) {
  const TriangleMesh original = porous_shell(6);
  TriangleMesh mesh = original;
  const DecimateOptions options{4, 0.05};
  const DecimateResult result = decimate_mesh(mesh, options);
  EXPECT_LT(result.triangles_after, result.triangles_before / 3);
  EXPECT_EQ(result.sampled.samples, 2 * kDeviationSamplesPerSide);
  EXPECT_LE(result.sampled.max(), options.max_distance);
  EXPECT_LE(result.max_distance, options.max_distance);
  const auto to_public = [](const TriangleMesh& m) {
    Mesh out;
    for (const Vec3& v : m.vertices) out.vertices.push_back({v.x(), v.y(), v.z()});
    for (const auto& t : m.triangles) out.triangles.push_back({t[0], t[1], t[2]});
    return out;
  };
  const double measured =
      test_support::sampled_two_sided_distance(to_public(original), to_public(mesh), 5000, 1.0);
  EXPECT_LE(measured, options.max_distance);
  // The check can fail: the same mesh moved by twice the bound is found that far off.
  TriangleMesh moved = mesh;
  for (Vec3& v : moved.vertices) v.x() += 2 * options.max_distance;
  EXPECT_GT(check_deviation(original, moved).max(), 1.5 * options.max_distance);
}

TEST(MeshDecimate, BoundsSettleMostCollapsesOnSmoothPartsAndChecksTheRest) {
  const TriangleMesh original = porous_shell(6);
  const auto reduce = [&](DistanceRule rule) {
    TriangleMesh mesh = original;
    DecimateOptions options{static_cast<std::int64_t>(original.triangles.size() / 8), 0.05};
    options.rule = rule;
    const DecimateResult result = decimate_mesh(mesh, options);
    expect_faithful(original, mesh, options, result);
    return result;
  };
  const DecimateResult both = reduce(DistanceRule::kBoundOrCheck), checks = reduce(DistanceRule::kCheckOnly);
  EXPECT_GT(both.collapses.bounded, both.collapses.checked);
  EXPECT_GT(both.collapses.checked, 0);  // the pores' rims
  EXPECT_EQ(checks.collapses.bounded, 0);
  // A bound within the tolerance keeps the points the checks ask about within it too: no fewer
  // collapses pass.
  EXPECT_LE(both.triangles_after, checks.triangles_after);
}

// Issue 49: collapses that place the vertex they keep where the quadrics are least, each measured against
// the original directly, reach fewer triangles within the same bound than the fans' bounds (about 0.6 on
// the demo bunny and the sphere r 50 mm), and still print the same part: the bound by an independent
// sampler, both ways, and by dense points on either surface.
TEST(MeshDecimate, PlacedCollapsesReachFewerTrianglesWithinTheSameBound) {
  const auto to_public = [](const TriangleMesh& m) {
    Mesh out;
    for (const Vec3& v : m.vertices) out.vertices.push_back({v.x(), v.y(), v.z()});
    for (const auto& t : m.triangles) out.triangles.push_back({t[0], t[1], t[2]});
    return out;
  };
  for (const auto& shape : {std::pair{torus(120, 40, 3.0, 1.0), 0.01}, std::pair{porous_shell(6), 0.05}}) {
    // Not a structured binding: clang 14's lambdas cannot capture one.
    const TriangleMesh& original = shape.first;
    const double max_distance = shape.second;
    const auto reduce = [&](DistanceRule rule, TriangleMesh& mesh) {
      mesh = original;
      DecimateOptions options{4, max_distance};
      options.rule = rule;
      const DecimateResult result = decimate_mesh(mesh, options);
      expect_faithful(original, mesh, options, result);
      return result;
    };
    TriangleMesh bounded, placed;
    const DecimateResult by_bounds = reduce(DistanceRule::kBoundOnly, bounded);
    const DecimateResult by_placing = reduce(DistanceRule::kPlaced, placed);
    EXPECT_LT(by_placing.triangles_after, 0.8 * static_cast<double>(by_bounds.triangles_after));
    EXPECT_EQ(by_placing.attempts, 1);  // its share of the bound leaves room for what lies between its points
    EXPECT_LE(test_support::sampled_two_sided_distance(to_public(original), to_public(placed), 5000, 1.0),
              max_distance);
    EXPECT_LE(largest_distance_over(placed, original, 8), max_distance);
    EXPECT_LE(largest_distance_over(original, placed, 3), max_distance);
    // The kept vertices moved off the original's: chords lie across the surface, not under it.
    std::set<std::array<double, 3>> original_vertices;
    for (const Vec3& p : original.vertices) original_vertices.insert({p.x(), p.y(), p.z()});
    const auto moved = std::count_if(placed.vertices.begin(), placed.vertices.end(), [&](const Vec3& p) {
      return original_vertices.count({p.x(), p.y(), p.z()}) == 0;
    });
    EXPECT_GT(moved, static_cast<std::ptrdiff_t>(placed.vertices.size() / 2));
  }
}

// Issue 49, item 3: a budget the fans' bounds reach is reached by them, at a fifth of a placed
// collapse's cost; one they stop short of, by placed collapses from the input. Both within the bound.
TEST(MeshDecimate, ABudgetTheFansBoundsReachIsReachedByThemFirst) {
  const TriangleMesh original = porous_shell(6);
  const auto n = static_cast<double>(original.triangles.size());
  const auto reduce = [&](double share, double max_distance) {
    TriangleMesh mesh = original;
    DecimateOptions options{static_cast<std::int64_t>(std::ceil(share * n)), max_distance};
    options.rule = DistanceRule::kPlaced;
    const DecimateResult result = decimate_mesh(mesh, options);
    expect_faithful(original, mesh, options, result);
    EXPECT_TRUE(result.reached_target) << share << " at " << max_distance;
    std::printf("budget %.2f of %.0f at %g: %lld triangles, %lld bounded, %lld checked, %d attempts\n", share,
                n, max_distance, static_cast<long long>(result.triangles_after),
                static_cast<long long>(result.collapses.bounded),
                static_cast<long long>(result.collapses.checked), result.attempts);
    return result;
  };
  const DecimateResult loose = reduce(kBoundsFirstShare, 0.05);
  EXPECT_GT(loose.collapses.bounded, 0);
  EXPECT_EQ(loose.collapses.checked, 0);
  EXPECT_EQ(loose.attempts, 1);
  const DecimateResult tight = reduce(kBoundsFirstShare, 0.02);  // the fans' bounds stop short here
  EXPECT_EQ(tight.collapses.bounded, 0);
  EXPECT_GT(tight.collapses.checked, 0);
  EXPECT_EQ(tight.attempts, 2);
  const DecimateResult small = reduce(0.25, 0.05);  // under the share: placed collapses at once
  EXPECT_EQ(small.collapses.bounded, 0);
  EXPECT_EQ(small.attempts, 1);
}

TEST(MeshDecimate, PlacedCollapsesAreTheSameOnAnyThreadCount) {
  const TriangleMesh original = porous_shell(2);
  TriangleMesh a = original, b = original;
  DecimateOptions options{4, 0.05};
  options.rule = DistanceRule::kPlaced;
  const DecimateResult ra = decimate_mesh(a, options);
  DecimateResult rb;
  {
    const tbb::global_control one_thread(tbb::global_control::max_allowed_parallelism, 1);
    rb = decimate_mesh(b, options);
  }
  ASSERT_LT(ra.triangles_after, ra.triangles_before / 2);
  EXPECT_EQ(a.vertices, b.vertices);
  EXPECT_EQ(a.triangles, b.triangles);
  EXPECT_EQ(ra.max_distance, rb.max_distance);
}

TEST(MeshDecimate, FlatFacesOfACubeCollapseExactly) {
  // Turned, so that round-off makes the error quadrics of flat collapses slightly negative.
  TriangleMesh original = tessellated_cube(12);  // 1728 triangles
  const Eigen::Matrix3d turn =
      (Eigen::AngleAxisd(0.3, Vec3::UnitZ()) * Eigen::AngleAxisd(0.5, Vec3::UnitX())).toRotationMatrix();
  for (Vec3& p : original.vertices) p = turn * p;
  TriangleMesh mesh = original;
  const DecimateOptions options{12, 1e-9};
  const DecimateResult result = decimate_mesh(mesh, options);
  expect_faithful(original, mesh, options, result);
  EXPECT_LT(result.triangles_after, result.triangles_before / 10);
  EXPECT_NEAR(analyze_topology(mesh).signed_volume, 1.0, 1e-12);
}

// A vertex no triangle uses is not part of the surface: it neither stops the reduction nor counts in
// the distance measured (the search over the result measured every vertex, and one 10 units off made
// every attempt overshoot).
TEST(MeshDecimate, AVertexNoTriangleUsesIsNotMeasured) {
  const TriangleMesh surface = torus(60, 20, 3.0, 1.0);
  TriangleMesh mesh = surface;
  mesh.vertices.emplace_back(10.0, 10.0, 10.0);
  const DecimateOptions options{600, 0.05};
  const DecimateResult result = decimate_mesh(mesh, options);
  EXPECT_TRUE(result.reached_target);
  EXPECT_LE(result.max_distance, options.max_distance);
  expect_faithful(surface, mesh, options, result);
}

TEST(MeshDecimate, DistanceBoundStopsBeforeTarget) {
  const TriangleMesh original = torus(60, 20, 3.0, 1.0);
  TriangleMesh mesh = original;
  const DecimateOptions options{4, 0.01};
  const DecimateResult result = decimate_mesh(mesh, options);
  EXPECT_FALSE(result.reached_target);
  EXPECT_GT(result.triangles_after, 4);
  EXPECT_LT(result.triangles_after, result.triangles_before);
  expect_faithful(original, mesh, options, result);
}

TEST(MeshDecimate, SameInputSameOutputOnAnyThreadCount) {
  const TriangleMesh original = porous_shell(2);
  const std::int64_t target = static_cast<std::int64_t>(original.triangles.size() / 2);
  TriangleMesh a = original, b = original;
  const DecimateResult ra = decimate(a, target, 0.1);
  DecimateResult rb;
  {
    const tbb::global_control one_thread(tbb::global_control::max_allowed_parallelism, 1);
    rb = decimate(b, target, 0.1);
  }
  ASSERT_LT(ra.triangles_after, ra.triangles_before);
  EXPECT_EQ(a.vertices, b.vertices);
  EXPECT_EQ(a.triangles, b.triangles);
  EXPECT_EQ(ra.max_distance, rb.max_distance);
}

TEST(MeshDecimate, MeshWithinTargetIsLeftUntouched) {
  const TriangleMesh original = torus(12, 6, 3.0, 1.0);  // 144 triangles
  for (std::int64_t target : {144, 1000}) {
    TriangleMesh mesh = original;
    const DecimateResult result = decimate(mesh, target, 0.1);
    EXPECT_TRUE(result.reached_target);
    EXPECT_EQ(result.triangles_before, 144);
    EXPECT_EQ(result.triangles_after, 144);
    EXPECT_EQ(result.max_distance, 0.0);
    EXPECT_EQ(mesh.vertices, original.vertices);
    EXPECT_EQ(mesh.triangles, original.triangles);
  }
}

TEST(MeshDecimate, RejectsBadOptions) {
  const TriangleMesh original = torus(12, 6, 3.0, 1.0);
  const double inf = std::numeric_limits<double>::infinity();
  for (const DecimateOptions& bad :
       {DecimateOptions{3, 0.1}, DecimateOptions{0, 0.1}, DecimateOptions{-5, 0.1}, DecimateOptions{100, 0.0},
        DecimateOptions{100, -0.1}, DecimateOptions{100, inf}, DecimateOptions{100, std::nan("")}}) {
    TriangleMesh mesh = original;
    EXPECT_THROW(decimate_mesh(mesh, bad), InputError) << bad.max_triangles << " " << bad.max_distance;
    EXPECT_EQ(mesh.triangles, original.triangles);
  }
}

TEST(MeshDecimate, RefusesVerticesThatAreNotNumbers) {
  for (const double bad : {std::nan(""), std::numeric_limits<double>::infinity()}) {
    TriangleMesh mesh = torus(24, 12, 3.0, 1.0);
    mesh.vertices[7].y() = bad;
    const TriangleMesh original = mesh;
    EXPECT_THROW(decimate(mesh, 100, 0.1), InputError) << bad;
    EXPECT_EQ(mesh.triangles, original.triangles);
  }
}

TEST(MeshDecimate, RefusesMeshThatIsNotPrintable) {
  TriangleMesh open = torus(24, 12, 3.0, 1.0);
  open.triangles.pop_back();  // a hole
  const TriangleMesh original = open;
  try {
    decimate(open, 100, 0.1);
    ADD_FAILURE() << "no exception";
  } catch (const InputError&) {
    ADD_FAILURE() << "an open mesh from the pipeline is a program error, not an input error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("boundary edges"), std::string::npos) << e.what();
  }
  EXPECT_EQ(open.triangles, original.triangles);

  TriangleMesh inside_out = torus(24, 12, 3.0, 1.0);
  for (auto& t : inside_out.triangles) std::swap(t[1], t[2]);
  EXPECT_THROW(decimate(inside_out, 100, 0.1), std::runtime_error);
}

}  // namespace
}  // namespace poreshell
