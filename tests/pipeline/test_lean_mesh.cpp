// Issue 49: by default the written mesh is reduced to the shape within `max_deviation` (0.02 mm) of the
// full isosurface of the same run (`max_deviation` 0), and it prints the same part: closed, manifold,
// oriented, one part, the same pores (Euler characteristic), the wall and the holes within 1 %, no
// triangle angle under 1 degree, the same bytes on 1 and 2 threads. The distance is measured here by an
// independent sampler (deviation_probe.hpp), both ways.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <numeric>
#include <string>

#include "deviation_probe.hpp"
#include "poreshell/poreshell.hpp"
#include "test_meshes.hpp"

using namespace poreshell;

namespace {

double mean_diameter(const Output& out) {
  double sum = 0.0;
  for (const Hole& h : out.holes) sum += h.diameter;
  return out.holes.empty() ? 0.0 : sum / static_cast<double>(out.holes.size());
}

// The default run against the full isosurface of the same request; `triangles` gets the reduced
// run's count.
void expect_same_part_fewer_triangles(const Input& input, Options options, const char* what,
                                      std::int64_t* triangles = nullptr) {
  options.threads = 2;
  Options full_options = options;
  full_options.max_deviation = 0.0;
  full_options.lean = false;  // nothing to reduce: refused with max_deviation 0
  const Result lean = perforate(input, options), full = perforate(input, full_options);
  ASSERT_EQ(lean.outputs.size(), 1u);
  const LevelReport &l = lean.report.outputs[0], &f = full.report.outputs[0];
  if (triangles) *triangles = l.topology.triangles;
  ASSERT_TRUE(l.reduction.has_value()) << what;
  EXPECT_FALSE(f.reduction.has_value()) << what << ": max_deviation 0 writes the full isosurface";
  const double bound = options.max_deviation;
  const double measured =
      test_support::sampled_two_sided_distance(lean.outputs[0].mesh, full.outputs[0].mesh, 20000, 10 * bound);
  std::printf(
      "%s: %lld -> %lld triangles, reported %.4f mm (sampled %.4f at %lld points), measured here "
      "%.4f mm; pores %lld / %lld; wall %.4f / %.4f mm; holes %zu / %zu, mean %.4f / %.4f mm; least "
      "angle %.2f deg\n",
      what, static_cast<long long>(f.topology.triangles), static_cast<long long>(l.topology.triangles),
      l.reduction->max_distance, l.reduction->sampled_distance,
      static_cast<long long>(l.reduction->sampled_points), measured,
      static_cast<long long>(l.pores_from_euler), static_cast<long long>(f.pores_from_euler), l.wall.median,
      f.wall.median, lean.outputs[0].holes.size(), full.outputs[0].holes.size(),
      mean_diameter(lean.outputs[0]), mean_diameter(full.outputs[0]), l.topology.min_angle_degrees);
  EXPECT_LE(measured, bound) << what;
  EXPECT_LE(l.reduction->max_distance, bound) << what;
  EXPECT_LE(l.reduction->sampled_distance, bound) << what;
  EXPECT_LT(l.topology.triangles, f.topology.triangles / 2) << what;
  EXPECT_TRUE(l.topology.closed && l.topology.manifold && l.topology.oriented) << what;
  EXPECT_EQ(l.topology.components, 1) << what;
  EXPECT_EQ(l.topology.euler_characteristic, f.topology.euler_characteristic) << what;
  EXPECT_EQ(l.pores_from_euler, f.pores_from_euler) << what;
  EXPECT_GE(l.topology.min_angle_degrees, 1.0) << what;
  EXPECT_NEAR(l.wall.median, f.wall.median, 0.01 * f.wall.median) << what;
  EXPECT_EQ(lean.outputs[0].holes.size(), full.outputs[0].holes.size()) << what;
  EXPECT_NEAR(mean_diameter(lean.outputs[0]), mean_diameter(full.outputs[0]),
              0.01 * mean_diameter(full.outputs[0]))
      << what;
  EXPECT_NEAR(l.topology.volume, f.topology.volume, 0.01 * f.topology.volume) << what;
}

TEST(LeanMesh, SphereKeepsItsPartWithinTheBound) {
  Options options;
  options.hole_diameter = 6.0;
  options.spacing = 10.0;
  options.wall = 2.0;
  expect_same_part_fewer_triangles(sphere(20.0), options, "sphere r 20, 6 mm at 10 mm");
}

TEST(LeanMesh, OpenSleeveKeepsItsPartWithinTheBound) {
  MeshInput input;
  input.mesh = test_support::open_sleeve(20.0, 40.0, 96, 24);
  input.name = "sleeve";
  Options options;
  options.hole_diameter = 6.0;
  options.spacing = 10.0;
  options.wall = 2.0;
  options.rim = 3.0;
  expect_same_part_fewer_triangles(input, options, "sleeve r 20 x 40, 6 mm at 10 mm");
}

// `lean`: the placed collapses (placed_collapse.hpp) keep the same part within the same bound in fewer
// triangles than the default's fan bounds.
TEST(LeanMesh, LeanKeepsThePartInFewerTriangles) {
  Options options;
  options.hole_diameter = 6.0;
  options.spacing = 10.0;
  options.wall = 2.0;
  options.threads = 2;
  const Result usual = perforate(sphere(20.0), options);
  options.lean = true;
  std::int64_t lean = 0;
  expect_same_part_fewer_triangles(sphere(20.0), options, "sphere r 20, 6 mm at 10 mm, lean", &lean);
  std::printf("lean %lld against %lld triangles\n", static_cast<long long>(lean),
              static_cast<long long>(usual.report.outputs[0].topology.triangles));
  EXPECT_GT(lean, 0);
  EXPECT_LT(static_cast<double>(lean), 0.8 * static_cast<double>(usual.report.outputs[0].topology.triangles));
}

TEST(LeanMesh, SameMeshOnOneAndTwoThreads) {
  Options options;
  options.hole_diameter = 8.0;
  options.spacing = 14.0;
  options.wall = 2.0;
  options.threads = 1;
  const Result one = perforate(sphere(20.0), options);
  options.threads = 2;
  const Result two = perforate(sphere(20.0), options);
  ASSERT_TRUE(one.report.outputs[0].reduction.has_value());
  EXPECT_EQ(one.outputs[0].mesh.vertices, two.outputs[0].mesh.vertices);
  EXPECT_EQ(one.outputs[0].mesh.triangles, two.outputs[0].mesh.triangles);
}

}  // namespace
