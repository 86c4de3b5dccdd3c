// The hole table through the whole pipeline: one record per pore the written mesh has (its Euler
// characteristic's count), on a closed sphere and on an open hemisphere whose edge cuts some spots into
// notches; diameters and spacings near the request, centres at the wall's middle, outward unit normals.

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>

#include "io/mesh_writers.hpp"
#include "pipeline/pipeline.hpp"
#include "pipeline/report.hpp"
#include "test_support.hpp"

namespace poreshell {
namespace {

// The upper half of a sphere of radius r about the origin, outward: open along the equator.
TriangleMesh upper_hemisphere(double r, int rings, int segments) {
  TriangleMesh m;
  m.vertices.push_back(Vec3(0, 0, r));
  for (int i = 1; i <= rings; ++i) {
    const double theta = 0.5 * std::numbers::pi * i / rings;
    for (int j = 0; j < segments; ++j) {
      const double phi = 2.0 * std::numbers::pi * j / segments;
      const double z = i == rings ? 0.0 : std::cos(theta);
      m.vertices.push_back(r * Vec3(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), z));
    }
  }
  const auto ring = [&](int i, int j) {
    return static_cast<std::int32_t>(1 + (i - 1) * segments + j % segments);
  };
  for (int j = 0; j < segments; ++j) m.triangles.push_back({0, ring(1, j), ring(1, j + 1)});
  for (int i = 1; i < rings; ++i)
    for (int j = 0; j < segments; ++j) {
      m.triangles.push_back({ring(i, j), ring(i + 1, j), ring(i + 1, j + 1)});
      m.triangles.push_back({ring(i, j), ring(i + 1, j + 1), ring(i, j + 1)});
    }
  return m;
}

// Every record: a round-ish hole of about the asked diameter, its centre `middle` from the origin (the
// wall's middle of a sphere about it), its normal unit and radial, outward; nearest neighbours about the
// asked spacing.
void expect_holes_as_asked(const HoleTable& table, double diameter, double spacing, double middle) {
  double sum_diameter = 0, sum_nearest = 0;
  for (const HoleRecord& h : table.holes) {
    EXPECT_GT(h.diameter, 0.7 * diameter);
    EXPECT_LT(h.diameter, 1.3 * diameter);
    EXPECT_GT(h.circularity, 0.8);
    EXPECT_LE(h.circularity, 1.0);
    EXPECT_NEAR(h.centre.norm(), middle, 0.02);
    EXPECT_NEAR(h.normal.norm(), 1.0, 1e-12);
    EXPECT_GT(h.normal.dot(h.centre.normalized()), 0.999);
    EXPECT_GT(h.nearest, 0.6 * spacing);
    EXPECT_LT(h.nearest, 1.4 * spacing);
    sum_diameter += h.diameter;
    sum_nearest += h.nearest;
  }
  const auto n = static_cast<double>(table.holes.size());
  double least = 1.0;
  for (const HoleRecord& h : table.holes) least = std::min(least, h.circularity);
  std::printf(
      "%zu holes (%zu seeds dropped): mean diameter %.2f mm, spacing %.2f mm, least circularity %.3f\n",
      table.holes.size(), table.dropped, sum_diameter / n, sum_nearest / n, least);
  EXPECT_NEAR(sum_diameter / n, diameter, 0.1 * diameter);
  EXPECT_NEAR(sum_nearest / n, spacing, 0.1 * spacing);
}

TEST(HoleTablePipeline, OneRecordPerPoreOfASphere) {
  const TempDir dir;
  PipelineConfig c;
  c.shape = "sphere";
  c.shape_radius = 20.0;
  c.holes = {6.0, 10.0, 0.0};
  c.wall = 2.0;
  c.output = dir / "sphere.stl";
  const PipelineResult r = run_pipeline(c);
  const MeshOutput& out = r.meshes.at(0);
  EXPECT_GT(out.pores_from_euler, 30);
  EXPECT_EQ(static_cast<std::int64_t>(out.hole_table.holes.size()), out.pores_from_euler);
  EXPECT_EQ(static_cast<std::int64_t>(out.hole_table.dropped), out.spots_at_iso - out.pores_from_euler);
  expect_holes_as_asked(out.hole_table, 6.0, 10.0, 20.0);
  const nlohmann::json report = to_json(r);
  EXPECT_EQ(report["mesh"]["hole_table"].size(), out.hole_table.holes.size());
  EXPECT_EQ(report["mesh"]["outputs"][0]["hole_table"][0]["centre"].size(), 3u);
}

// An open sheet, its wall outside the surface: the spots the edge cuts are notches, not pores, and
// measure no closed loop.
TEST(HoleTablePipeline, OneRecordPerPoreOfAnOpenHemisphere) {
  const TempDir dir;
  PipelineConfig c;
  c.mesh = dir / "hemisphere.obj";
  write_mesh(c.mesh, upper_hemisphere(25.0, 48, 192));
  c.holes = {6.0, 10.0, 0.0};
  c.wall = 1.5;
  c.offset = "outside";
  c.output = dir / "hemisphere.stl";
  const PipelineResult r = run_pipeline(c);
  const MeshOutput& out = r.meshes.at(0);
  EXPECT_GT(out.pores_from_euler, 20);
  EXPECT_GT(out.spots_at_iso, out.pores_from_euler) << "no notch along the edge";
  EXPECT_EQ(static_cast<std::int64_t>(out.hole_table.holes.size()), out.pores_from_euler);
  EXPECT_EQ(static_cast<std::int64_t>(out.hole_table.dropped), out.spots_at_iso - out.pores_from_euler);
  expect_holes_as_asked(out.hole_table, 6.0, 10.0, 25.0 + 0.75);
}

}  // namespace
}  // namespace poreshell
