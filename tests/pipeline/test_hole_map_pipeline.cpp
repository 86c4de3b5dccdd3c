// The hole map (issue 4, item 3) and grading (item 4) through the whole pipeline: hole diameter and spacing
// asked in mm come out of the whole pipeline within 15% on a sphere and an open cylinder; impossible requests
// are refused with the nearest feasible one; graded holes grow along the axis and never merge.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <string>
#include <vector>

#include "pattern/grading.hpp"
#include "pipeline/pipeline.hpp"
#include "pipeline/report.hpp"
#include "poreshell/io.hpp"
#include "test_meshes.hpp"
#include "test_support.hpp"

using namespace poreshell;
namespace fs = std::filesystem;

namespace {

double relative_error(double measured, double asked) {
  return std::abs(measured - asked) / asked;
}

// An open cylinder (no caps) about the z axis, written as OBJ: a sheet with two boundary circles.
fs::path write_open_cylinder(const fs::path& dir, double radius, double height) {
  const fs::path path = dir / "cylinder.obj";
  test_support::write_obj_text(path, test_support::open_sleeve(radius, height, 96, 40));
  return path;
}

// A UV sphere of radius r as ASCII PLY with two painted vertex properties: keepout = 1 on the cap
// z > cap_z, and hole_mm rising linearly from 4 mm at the south pole to 7.5 mm at the north pole.
fs::path write_painted_sphere(const fs::path& dir, double r, double cap_z) {
  const int rings = 48, segments = 96;
  std::vector<Vec3> v{Vec3(0, 0, -r)};
  for (int i = 1; i < rings; ++i)
    for (int j = 0; j < segments; ++j) {
      const double theta = std::numbers::pi * i / rings, phi = 2 * std::numbers::pi * j / segments;
      v.emplace_back(r * std::sin(theta) * std::cos(phi), r * std::sin(theta) * std::sin(phi),
                     -r * std::cos(theta));
    }
  v.emplace_back(0, 0, r);
  const auto at = [&](int i, int j) { return 1 + (i - 1) * segments + j % segments; };
  std::vector<std::array<int, 3>> f;
  for (int j = 0; j < segments; ++j) {
    f.push_back({0, at(1, j + 1), at(1, j)});
    f.push_back({static_cast<int>(v.size()) - 1, at(rings - 1, j), at(rings - 1, j + 1)});
  }
  for (int i = 1; i < rings - 1; ++i)
    for (int j = 0; j < segments; ++j) {
      f.push_back({at(i, j), at(i, j + 1), at(i + 1, j + 1)});
      f.push_back({at(i, j), at(i + 1, j + 1), at(i + 1, j)});
    }
  const fs::path path = dir / "painted.ply";
  std::ofstream out(path);
  out << "ply\nformat ascii 1.0\nelement vertex " << v.size()
      << "\nproperty float x\nproperty float y\nproperty float z\nproperty uchar keepout\nproperty float "
         "hole_mm\n"
      << "element face " << f.size() << "\nproperty list uchar int vertex_indices\nend_header\n";
  for (const Vec3& p : v)
    out << p.x() << ' ' << p.y() << ' ' << p.z() << ' ' << (p.z() > cap_z ? 1 : 0) << ' '
        << 4.0 + 3.5 * (p.z() + r) / (2 * r) << '\n';
  for (const auto& t : f) out << "3 " << t[0] << ' ' << t[1] << ' ' << t[2] << '\n';
  return path;
}

// Every printed pore is a hole on the band and a tunnel of the written mesh.
void expect_holes_are_tunnels(const MeshOutput& out) {
  EXPECT_TRUE(out.topology.closed() && out.topology.manifold() && out.topology.oriented());
  EXPECT_GT(out.topology.min_angle_degrees, 1.0) << "no slivers";
  EXPECT_EQ(out.pores_from_euler, out.spots_at_iso);
}

}  // namespace

TEST(HoleMapPipeline, SphereOfRadius50GivesTheAskedHolesWallAndPores) {
  Options c;
  c.hole_diameter = 6.0;
  c.spacing = 10.0;
  c.wall = 2.0;
  const PipelineResult r = run_pipeline(sphere(50.0), c, unmonitored());
  ASSERT_EQ(r.meshes.size(), 1u);
  const MeshOutput& out = r.meshes.front();
  EXPECT_LT(relative_error(out.holes.diameter_mean, 6.0), 0.15) << out.holes.diameter_mean;
  EXPECT_LT(relative_error(out.holes.spacing_mean, 10.0), 0.15) << out.holes.spacing_mean;
  EXPECT_LT(out.holes.diameter_cv, 0.15);
  EXPECT_GT(out.wall.probes, 100u);
  EXPECT_LT(relative_error(out.wall.median, 2.0), 0.10) << out.wall.median;
  expect_holes_are_tunnels(out);
  // About one hole per hexagonal cell of the sphere's area.
  const double cells = 4 * std::numbers::pi * 50 * 50 / (std::sqrt(3.0) / 2 * 10 * 10);
  EXPECT_NEAR(static_cast<double>(out.holes.holes.size()), cells, 0.25 * cells);
}

// Issue 19's uniformity on a CI-sized sphere (r = 30 mm, 6 mm at 10 mm, about 107 holes). Over seeds 1-4
// the report's cell-area CV was 0.073-0.084 with the paper's layout and 0.052-0.063 with cvt, the NN CV
// 0.046-0.052 and 0.036-0.046, the hole counts equal per seed; the bounds leave a little room.
TEST(HoleMapPipeline, CvtLayoutIsMoreEvenThanTheEquationsOwnWithTheSameHoles) {
  Options c;
  c.hole_diameter = 6.0;
  c.spacing = 10.0;
  c.wall = 2.0;
  c.layout = Layout::paper;
  const PipelineResult paper = run_pipeline(sphere(30.0), c, unmonitored());
  c.layout = Layout::automatic;  // cvt for holes in mm
  const PipelineResult cvt = run_pipeline(sphere(30.0), c, unmonitored());
  ASSERT_EQ(cvt.solve.layout, Layout::cvt);
  const HoleStats &a = paper.meshes.front().holes, &b = cvt.meshes.front().holes;
  EXPECT_NEAR(static_cast<double>(b.holes.size()), static_cast<double>(a.holes.size()),
              0.02 * static_cast<double>(a.holes.size()));
  EXPECT_LT(b.cell_area_cv, 0.066);
  EXPECT_LT(b.cell_area_cv, a.cell_area_cv - 0.01);
  EXPECT_LT(b.spacing_cv, 0.050);
  EXPECT_LT(b.diameter_cv, a.diameter_cv + 0.005);
  EXPECT_LT(relative_error(b.diameter_mean, 6.0), 0.05) << b.diameter_mean;
  // The equation keeps the discs it started from.
  EXPECT_EQ(static_cast<std::int64_t>(b.holes.size()), cvt.solve.layout_holes);
  std::printf("cell-area CV %.4f -> %.4f, NN CV %.4f -> %.4f, %zu -> %zu holes\n", a.cell_area_cv,
              b.cell_area_cv, a.spacing_cv, b.spacing_cv, a.holes.size(), b.holes.size());
}

TEST(HoleMapPipeline, OpenCylinderWithRimGivesTheAskedHolesAndWallReducedToATriangleBudget) {
  const TempDir dir;
  const Input cylinder = load_mesh(write_open_cylinder(dir.path(), 25.0, 60.0));
  Options c;
  c.hole_diameter = 5.0;
  c.spacing = 8.0;
  c.wall = 1.5;
  c.rim = 2.0;
  c.max_triangles = 150000;  // from about 590,000
  const PipelineResult r = run_pipeline(cylinder, c, unmonitored());
  const MeshOutput& out = r.meshes.front();
  ASSERT_TRUE(out.reduction);
  EXPECT_LE(out.topology.triangles, 150000);
  EXPECT_LE(out.reduction->max_distance, c.max_deviation);
  EXPECT_LT(relative_error(out.holes.diameter_mean, 5.0), 0.15) << out.holes.diameter_mean;
  EXPECT_LT(relative_error(out.holes.spacing_mean, 8.0), 0.15) << out.holes.spacing_mean;
  EXPECT_LT(relative_error(out.wall.median, 1.5), 0.10) << out.wall.median;
  expect_holes_are_tunnels(out);
  for (const BandHole& hole : out.holes.holes) {  // no hole cut by the open ends
    EXPECT_GT(hole.centroid.z() - hole.diameter / 2, 2.0 - 0.5);
    EXPECT_LT(hole.centroid.z() + hole.diameter / 2, 60.0 - 2.0 + 0.5);
  }
}

// Voxels half the map's size (a smoother surface): the equation's own layout is formed on the map's grid
// and carried (the coarse start), with the rim's solid zone on both grids; the holes are the asked ones.
// (The even layout starts from discs on the fine grid: no coarse start.)
TEST(HoleMapPipeline, FinerVoxelsKeepTheHolesAndTheRimThroughTheCoarseStart) {
  const TempDir dir;
  const Input cylinder = load_mesh(write_open_cylinder(dir.path(), 25.0, 60.0));
  Options c;
  c.hole_diameter = 5.0;
  c.spacing = 8.0;
  c.voxel_size = 0.5 * plan_pattern({5.0, 8.0, 0.0}).voxel_size;
  c.wall = 1.5;
  c.rim = 2.0;
  c.layout = Layout::paper;
  const PipelineResult r = run_pipeline(cylinder, c, unmonitored());
  ASSERT_TRUE(r.solve.coarse_start);
  EXPECT_NEAR(r.solve.coarse_start->h, 2.0 * r.h, 0.02 * r.h);
  EXPECT_TRUE(r.solve.run.reached_tolerance);
  EXPECT_LE(r.solve.run.steps * 5, r.solve.coarse_start->run.steps);
  const MeshOutput& out = r.meshes.front();
  EXPECT_LT(relative_error(out.holes.diameter_mean, 5.0), 0.15) << out.holes.diameter_mean;
  EXPECT_LT(relative_error(out.holes.spacing_mean, 8.0), 0.15) << out.holes.spacing_mean;
  expect_holes_are_tunnels(out);
  for (const BandHole& hole : out.holes.holes) {  // the rim held on both grids
    EXPECT_GT(hole.centroid.z() - hole.diameter / 2, 2.0 - 0.5);
    EXPECT_LT(hole.centroid.z() + hole.diameter / 2, 60.0 - 2.0 + 0.5);
  }
}

TEST(HoleMapPipeline, GradedHolesGrowAlongTheAxisAndNeverMerge) {
  Options c;
  c.hole_diameter = 6.0;
  c.spacing = 10.0;
  const PipelineResult uniform = run_pipeline(sphere(30.0), c, unmonitored());
  c.grade = parse_grade("axis:z:4:7.5");
  const PipelineResult graded = run_pipeline(sphere(30.0), c, unmonitored());
  const MeshOutput& out = graded.meshes.front();
  expect_holes_are_tunnels(out);
  // Same pattern, same holes: none merged with a neighbour, none closed.
  EXPECT_EQ(out.holes.holes.size(), uniform.meshes.front().holes.holes.size());
  ASSERT_TRUE(graded.grading);
  EXPECT_EQ(graded.grading->clamped_fraction, 0.0);
  // Mean diameter in four slabs along z rises slab by slab.
  std::array<double, 4> sum{}, count{};
  for (const BandHole& hole : out.holes.holes) {
    const auto slab = static_cast<std::size_t>(std::clamp((hole.centroid.z() + 30.0) / 15.0, 0.0, 3.999));
    sum[slab] += hole.diameter;
    count[slab] += 1;
  }
  for (std::size_t s = 1; s < 4; ++s) EXPECT_GT(sum[s] / count[s], sum[s - 1] / count[s - 1]) << s;
  EXPECT_GT(sum[3] / count[3] - sum[0] / count[0], 1.5);
}

TEST(HoleMapPipeline, PaintedFieldsGradeHolesAndKeepACapSolid) {
  const TempDir dir;
  const Input painted =
      load_mesh(write_painted_sphere(dir.path(), 30.0, 15.0), Unit::mm, {"hole_mm", "keepout"});
  Options c;
  c.hole_diameter = 6.0;
  c.spacing = 10.0;
  c.grade = parse_grade("field:hole_mm");
  c.keep_out_mask = "keepout";
  const PipelineResult r = run_pipeline(painted, c, unmonitored());
  const MeshOutput& out = r.meshes.front();
  expect_holes_are_tunnels(out);
  ASSERT_TRUE(r.grading);
  EXPECT_NEAR(r.grading->min_diameter, 4.0, 0.3);
  EXPECT_NEAR(r.grading->max_diameter, 7.5, 0.3);
  double low = 0, low_n = 0, high = 0, high_n = 0;
  for (const BandHole& hole : out.holes.holes) {
    EXPECT_LT(hole.centroid.z() + hole.diameter / 2, 15.0 + 1.0) << "a hole in the kept-out cap";
    (hole.centroid.z() < -10 ? low : high) += hole.diameter;
    (hole.centroid.z() < -10 ? low_n : high_n) += 1;
  }
  EXPECT_GT(high / high_n - low / low_n, 1.0) << "holes follow the painted diameters";
}

// The report's solid-zone areas on any input, not only meshes (issue 51): on a sphere of radius 30 a
// keep-out ball of radius 10 centred on the surface keeps a cap of area pi 10^2 (within a chord of
// 10 of a point of a sphere), of the sphere's 4 pi 30^2. Before, inputs other than meshes reported zeros
// and the low-porosity warning blamed no rule.
TEST(HoleMapPipeline, SolidZoneAreasOfAShapeAreMeasured) {
  Options c;
  c.hole_diameter = 6.0;
  c.spacing = 10.0;
  c.preview = true;
  c.keep_out.push_back({{30.0, 0.0, 0.0}, 10.0});
  const PipelineResult r = run_pipeline(sphere(30.0), c, unmonitored());
  EXPECT_LT(relative_error(r.zone_areas.surface, 4 * std::numbers::pi * 30 * 30), 0.03)
      << r.zone_areas.surface;
  EXPECT_LT(relative_error(r.zone_areas.keep_outs, std::numbers::pi * 10 * 10), 0.05)
      << r.zone_areas.keep_outs;
  EXPECT_DOUBLE_EQ(r.zone_areas.solid, r.zone_areas.keep_outs);
  EXPECT_EQ(r.zone_areas.thin + r.zone_areas.creases + r.zone_areas.rims, 0.0);
  ASSERT_EQ(r.zone_areas.each_keep_out.size(), 1u);
  EXPECT_EQ(r.zone_areas.each_keep_out[0].area, r.zone_areas.keep_outs);
  EXPECT_EQ(r.zone_areas.each_keep_out[0].gap_mm, 0.0);
}

// On an open sleeve (r 25 mm, 60 mm long) the report's areas are the sheet's: its surface 2 pi 25 60 and
// the rims 2 x 2 pi 25 w, along the grid's axes (its rows on the edges) and tilted off them. Before,
// counting whole voxels, a 4 mm rim came out 17 % under or 3 % over as the rows fell (issue 51).
TEST(HoleMapPipeline, RimAreaOfAnOpenSleeveIsTheSheets) {
  for (const double tilt : {0.0, 0.5}) {  // radians about x
    MeshInput sleeve;
    sleeve.mesh = test_support::open_sleeve(25.0, 60.0);
    for (Point& p : sleeve.mesh.vertices)
      p = {p[0], std::cos(tilt) * p[1] - std::sin(tilt) * p[2],
           std::sin(tilt) * p[1] + std::cos(tilt) * p[2]};
    for (const double rim : {3.0, 4.0}) {
      Options c;
      c.hole_diameter = 6.0;
      c.spacing = 10.0;
      c.rim = rim;
      c.preview = true;
      const PipelineResult r = run_pipeline(Input(sleeve), c, unmonitored());
      const double circumference = 2 * std::numbers::pi * 25;
      EXPECT_LT(relative_error(r.zone_areas.surface, circumference * 60), 0.01)
          << "tilt " << tilt << ": " << r.zone_areas.surface;
      EXPECT_LT(relative_error(r.zone_areas.rims, 2 * circumference * rim), 0.03)
          << "tilt " << tilt << ", rim " << rim << ": " << r.zone_areas.rims;
      std::printf("tilt %.1f rim %.0f: surface %.1f (%.1f), rims %.1f (%.1f)\n", tilt, rim,
                  r.zone_areas.surface, circumference * 60, r.zone_areas.rims, 2 * circumference * rim);
    }
  }
}

// A keep-out inside the model's bounds that reaches no surface (in a hollow sphere's middle) keeps
// nothing: the report says so, with how far the surface is (issue 51); one on the surface is not named,
// nor one outside the model's bounds, which the estimate names before the run.
TEST(HoleMapPipeline, AKeepOutThatReachesNoSurfaceIsSaid) {
  Options c;
  c.hole_diameter = 6.0;
  c.spacing = 10.0;
  c.preview = true;
  c.keep_out = {{{0.0, 0.0, 0.0}, 12.0}, {{0.0, 0.0, 30.0}, 5.0}, {{460.0, 0.0, 0.0}, 5.0}};
  c.keep_out_boxes = {{{-5.0, -5.0, -5.0}, {5.0, 5.0, 5.0}}};
  const PipelineResult r = run_pipeline(sphere(30.0), c, unmonitored());
  ASSERT_EQ(r.zone_areas.each_keep_out.size(), 4u);
  EXPECT_NEAR(r.zone_areas.each_keep_out[0].gap_mm, 18.0, 0.5);
  EXPECT_GT(r.zone_areas.each_keep_out[1].area, 0.0);
  EXPECT_TRUE(r.zone_areas.each_keep_out[2].outside_bounds);
  EXPECT_FALSE(r.zone_areas.each_keep_out[3].outside_bounds);
  EXPECT_NEAR(r.zone_areas.each_keep_out[3].gap_mm, 30.0 - 5.0 * std::sqrt(3.0), 0.5);
  std::vector<std::string> said;
  for (const std::string& w : make_report(r, c).warnings)
    if (w.find("keeps none of the model's surface") != std::string::npos) said.push_back(w);
  ASSERT_EQ(said.size(), 2u);
  EXPECT_NE(said[0].find("`keep_out` 0,0,0,12"), std::string::npos) << said[0];
  EXPECT_NE(said[0].find("18"), std::string::npos) << said[0];
  EXPECT_NE(said[1].find("`keep_out_boxes` -5,-5,-5,5,5,5"), std::string::npos) << said[1];
}
