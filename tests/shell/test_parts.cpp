// One part: specks and sealed voids below the threshold go, parts of comparable size stay.

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "shell/parts.hpp"
#include "test_meshes.hpp"

using namespace poreshell;

namespace {

// A closed UV sphere of radius r at c (12 rings, 24 segments), outward (or inward when `inward`).
void add_sphere(TriangleMesh& m, const Vec3& c, double r, bool inward = false) {
  const Mesh sphere = test_support::uv_sphere(r, 12, 24);
  test_support::append(m, inward ? test_support::inverted(sphere) : sphere, c);
}

TEST(Parts, SpecksAndSealedVoidsGoComparablePartsStay) {
  TriangleMesh m;
  add_sphere(m, Vec3(0, 0, 0), 10.0);
  add_sphere(m, Vec3(30, 0, 0), 8.0);        // a second body: half the volume, kept
  add_sphere(m, Vec3(0, 20, 0), 0.5);        // a speck
  add_sphere(m, Vec3(2, 0, 0), 1.0, true);   // a sealed void inside the first body
  add_sphere(m, Vec3(30, 0, 0), 5.0, true);  // a large cavity inside the second: a design, kept
  const std::size_t before = m.triangles.size();
  const PartsSummary s = keep_main_parts(m, 0.01);
  EXPECT_EQ(s.parts, 2);
  EXPECT_EQ(s.removed_fragments, 1);
  EXPECT_EQ(s.removed_voids, 1);
  // The void, for the caller's test against the wall without pores: a point in it, and a sphere's chi.
  ASSERT_EQ(s.voids.size(), 1u);
  EXPECT_LT((s.voids[0].inside - Vec3(2, 0, 0)).norm(), 1e-9);
  EXPECT_EQ(s.voids[0].euler_characteristic, 2);
  const double speck = 4.0 / 3.0 * std::numbers::pi * 0.125, hollow = 4.0 / 3.0 * std::numbers::pi;
  EXPECT_NEAR(s.removed_volume, speck + hollow,
              0.1 * (speck + hollow));                       // inscribed polyhedra: a little less
  EXPECT_EQ(m.triangles.size(), before - 2 * (before / 5));  // every sphere has the same triangle count
  const MeshTopology t = analyze_topology(m);
  EXPECT_EQ(t.components, 3);  // two bodies and the kept cavity
  EXPECT_TRUE(t.closed() && t.manifold() && t.oriented());
  for (const auto& tri : m.triangles)
    for (std::int32_t v : tri) EXPECT_LT(static_cast<std::size_t>(v), m.vertices.size());
}

TEST(Parts, NothingToRemoveLeavesTheMeshAsItIs) {
  TriangleMesh m;
  add_sphere(m, Vec3(0, 0, 0), 10.0);
  const TriangleMesh copy = m;
  const PartsSummary s = keep_main_parts(m, 0.01);
  EXPECT_EQ(s.parts, 1);
  EXPECT_EQ(s.removed_fragments + s.removed_voids, 0);
  EXPECT_EQ(m.vertices, copy.vertices);
  EXPECT_EQ(m.triangles, copy.triangles);
}

}  // namespace

// Issue 51: a perforated solid's sealed cavity traps resin whatever its size; with fill_cavities every
// inward component goes (its sheet removed, the cavity is solid), the large ones counted as filled.
TEST(Parts, FillCavitiesRemovesEverySealedCavity) {
  TriangleMesh m;
  add_sphere(m, Vec3(0, 0, 0), 10.0);
  add_sphere(m, Vec3(30, 0, 0), 8.0);        // a second body, kept
  add_sphere(m, Vec3(2, 0, 0), 1.0, true);   // a small void: removed as before
  add_sphere(m, Vec3(30, 0, 0), 5.0, true);  // a large cavity: filled
  const PartsSummary s = keep_main_parts(m, 0.01, true);
  EXPECT_EQ(s.parts, 2);
  EXPECT_EQ(s.removed_voids, 1);
  ASSERT_EQ(s.voids.size(), 1u);  // the large one is no pocket of the wall for the Euler count
  EXPECT_EQ(s.filled_cavities, 1);
  const double cavity = 4.0 / 3.0 * std::numbers::pi * 125.0;
  EXPECT_NEAR(s.filled_volume, cavity, 0.1 * cavity);
  EXPECT_DOUBLE_EQ(s.largest_filled_volume, s.filled_volume);
  const MeshTopology t = analyze_topology(m);
  EXPECT_EQ(t.components, 2);
  EXPECT_TRUE(t.closed() && t.manifold() && t.oriented());
}
