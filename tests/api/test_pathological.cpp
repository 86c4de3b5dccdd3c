// Pathological inputs end in moments (issue 47, item 4): repeats of a triangle, from a polygon fanned over
// a few coincident corners or an object placed many times at one spot, are dropped before anything is
// built on them, and counted in the report.

#include <gtest/gtest.h>

#include <string>

#include "io/mesh_io.hpp"
#include "poreshell/poreshell.hpp"

using namespace poreshell;

namespace {

const char* const kCubeCorners =
    "v 0 0 0\nv 20 0 0\nv 20 20 0\nv 0 20 0\nv 0 0 20\nv 20 0 20\nv 20 20 20\nv 0 20 20\n";

// An OBJ polygon of 4,000 corners going round a cube's 8 (the audit's 23 s input).
TEST(Pathological, APolygonOverFewCornersKeepsEachTriangleOnce) {
  std::string obj = kCubeCorners;
  obj += "f";
  for (int k = 0; k < 4000; ++k) {
    obj += ' ';  // appended apart: g++ 12's -Wrestrict misfires on " " + std::to_string(...)
    obj += std::to_string(1 + k % 8);
  }
  obj += "\n";
  MeshInputStats stats;
  const TriangleMesh mesh = read_triangle_mesh_bytes(obj, ".obj", "polygon.obj", &stats);
  EXPECT_LE(mesh.triangles.size(), 56u) << "at most one triangle per three of the 8 corners";
  EXPECT_EQ(stats.dropped_degenerate + stats.dropped_duplicate + stats.triangles, 3998);
  EXPECT_GT(stats.dropped_duplicate, 2900);
}

// A closed cube given 500 times over (as a 3MF placing one object many times at one spot): one cube, the
// repeats counted in the report.
TEST(Pathological, AnObjectRepeatedInPlaceIsReadOnceAndCounted) {
  const Mesh one = [] {
    Mesh m;
    for (int k = 0; k < 8; ++k)
      m.vertices.push_back({20.0 * (k == 1 || k == 2 || k == 5 || k == 6),
                            20.0 * (k == 2 || k == 3 || k == 6 || k == 7), 20.0 * (k >= 4)});
    m.triangles = {{0, 2, 1}, {0, 3, 2}, {4, 5, 6}, {4, 6, 7}, {0, 1, 5}, {0, 5, 4},
                   {2, 3, 7}, {2, 7, 6}, {1, 2, 6}, {1, 6, 5}, {0, 4, 7}, {0, 7, 3}};
    return m;
  }();
  MeshInput many;
  for (int copy = 0; copy < 500; ++copy) {
    const auto base = static_cast<std::int32_t>(many.mesh.vertices.size());
    many.mesh.vertices.insert(many.mesh.vertices.end(), one.vertices.begin(), one.vertices.end());
    for (const Triangle& t : one.triangles)
      many.mesh.triangles.push_back({base + t[0], base + t[1], base + t[2]});
  }
  Options o;
  o.resolution = 25;
  o.max_steps = 3;
  o.threads = 2;
  const Result r = perforate(many, o);
  EXPECT_EQ(r.report.input.triangles, 12);
  EXPECT_EQ(r.report.input.vertices, 8);
  EXPECT_EQ(r.report.input.dropped_duplicate, 12 * 499);
  EXPECT_EQ(r.report.input.boundary_edges, 0);
}

}  // namespace
