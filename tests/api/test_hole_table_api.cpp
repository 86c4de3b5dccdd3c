// The hole table through the public API: one record per pore the written mesh has (its Euler
// characteristic's count), on a closed sphere and on an open hemisphere whose edge cuts some spots into
// notches; diameters and spacings near the request, centres at the wall's middle, outward unit normals.

#include <gtest/gtest.h>
#include <optional>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <numbers>

#include "poreshell/poreshell.hpp"
#include "test_meshes.hpp"

namespace poreshell {
namespace {

using test_support::upper_hemisphere;

// Every record: a round-ish hole of about the asked diameter, its centre `middle` from the origin (the
// wall's middle of a sphere about it), its normal unit and radial, outward; nearest neighbours about the
// asked spacing.
double norm(const Point& p) {
  return std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
}

void expect_holes_as_asked(const std::vector<Hole>& holes, std::int64_t dropped, double diameter,
                           double spacing, double middle) {
  double sum_diameter = 0, sum_nearest = 0;
  for (const Hole& h : holes) {
    EXPECT_GT(h.diameter, 0.7 * diameter);
    EXPECT_LT(h.diameter, 1.3 * diameter);
    EXPECT_GT(h.circularity, 0.8);
    EXPECT_LE(h.circularity, 1.0);
    EXPECT_NEAR(norm(h.centre), middle, 0.02);
    EXPECT_NEAR(norm(h.normal), 1.0, 1e-12);
    EXPECT_GT(
        (h.normal[0] * h.centre[0] + h.normal[1] * h.centre[1] + h.normal[2] * h.centre[2]) / norm(h.centre),
        0.999);
    EXPECT_GT(h.nearest, 0.6 * spacing);
    EXPECT_LT(h.nearest, 1.4 * spacing);
    sum_diameter += h.diameter;
    sum_nearest += h.nearest;
  }
  const auto n = static_cast<double>(holes.size());
  double least = 1.0;
  for (const Hole& h : holes) least = std::min(least, h.circularity);
  std::printf(
      "%zu holes (%lld seeds dropped): mean diameter %.2f mm, spacing %.2f mm, least circularity %.3f\n",
      holes.size(), static_cast<long long>(dropped), sum_diameter / n, sum_nearest / n, least);
  EXPECT_NEAR(sum_diameter / n, diameter, 0.1 * diameter);
  EXPECT_NEAR(sum_nearest / n, spacing, 0.1 * spacing);
}

TEST(HoleTablePipeline, OneRecordPerPoreOfASphere) {
  Options c;
  c.hole_diameter = 6.0;
  c.spacing = 10.0;
  c.wall = 2.0;
  const Result r = perforate(sphere(20.0), c);
  const LevelReport& out = r.report.outputs.at(0);
  const std::vector<Hole>& holes = r.outputs.at(0).holes;
  EXPECT_GT(out.pores_from_euler, 30);
  EXPECT_EQ(static_cast<std::int64_t>(holes.size()), out.pores_from_euler);
  EXPECT_EQ(out.hole_table_dropped, out.spots_at_iso - out.pores_from_euler);
  // Each spot without a pore is said to be a notch at the open edge (issue 51: the counts differed
  // without a word).
  EXPECT_EQ(out.spots_at_open_edge, out.hole_table_dropped);
  EXPECT_EQ(out.spots_not_through, 0);
  expect_holes_as_asked(holes, out.hole_table_dropped, 6.0, 10.0, 20.0);
  // Issue 19, item 5, round pores: mean 4 pi A / P^2 of the mid-wall loops at least 0.97, none under
  // 0.90. Measured here: mean 0.990, least 0.983; on r = 50 (297 holes) 0.991 and 0.977. Before the
  // shell was meshed from its two parts (isosurface.hpp), 0.956 and 0.930 on r = 50: the chamfer at the
  // pores' rims made each loop's outline zigzag.
  double circularity = 0.0, least = 1.0;
  for (const Hole& h : holes) {
    circularity += h.circularity / static_cast<double>(holes.size());
    least = std::min(least, h.circularity);
  }
  std::printf("circularity: mean %.3f, least %.3f\n", circularity, least);
  EXPECT_GE(circularity, 0.97);
  EXPECT_GE(least, 0.90);
  const nlohmann::json report = nlohmann::json::parse(report_json(r.report, r.outputs));
  EXPECT_EQ(report["mesh"]["hole_table"].size(), holes.size());
  EXPECT_EQ(report["mesh"]["outputs"][0]["hole_table"][0]["centre"].size(), 3u);
}

// An open sheet, its wall outside the surface: the spots the edge cuts are notches, not pores, and
// measure no closed loop. Most are closed before meshing as pinholes (under 0.76 D by their band area),
// so most seeds leave none: the first seed that leaves one is taken, for the table to have one to drop.
TEST(HoleTablePipeline, OneRecordPerPoreOfAnOpenHemisphere) {
  MeshInput hemisphere;
  hemisphere.mesh = upper_hemisphere(25.0, 48, 192);
  Options c;
  c.hole_diameter = 6.0;
  c.spacing = 10.0;
  c.wall = 1.5;
  c.offset = WallOffset::outside;
  c.thin_feature_ratio = 0.0;  // the sheet is a surface, not a thin part: measure every pore
  c.crease_angle = 0.0;
  c.layout = Layout::paper;  // its spots cut by the edge are the notches the table must drop (cvt has none)
  c.rim = 0.0;  // no rim: the notches are the point (the default rim since issue 51 keeps holes off the edge)
  std::optional<Result> notched;
  for (std::uint64_t seed : {4, 1, 2, 3, 5, 6, 7, 8}) {  // 4 the first that leaves one today
    if (notched) break;
    c.seed = seed;
    Result r = perforate(hemisphere, c);
    const LevelReport& level = r.report.outputs.at(0);
    if (level.spots_at_iso > level.pores_from_euler) notched = std::move(r);
  }
  ASSERT_TRUE(notched) << "no notch along the edge with seeds 1-8";
  std::printf("the first notch: seed %llu\n", static_cast<unsigned long long>(c.seed));
  const Result& r = *notched;
  const LevelReport& out = r.report.outputs.at(0);
  const std::vector<Hole>& holes = r.outputs.at(0).holes;
  EXPECT_GT(out.pores_from_euler, 20);
  EXPECT_EQ(static_cast<std::int64_t>(holes.size()), out.pores_from_euler);
  EXPECT_EQ(out.hole_table_dropped, out.spots_at_iso - out.pores_from_euler);
  // Each spot without a pore is said to be a notch at the open edge (issue 51: the counts differed
  // without a word).
  EXPECT_EQ(out.spots_at_open_edge, out.hole_table_dropped);
  EXPECT_EQ(out.spots_not_through, 0);
  expect_holes_as_asked(holes, out.hole_table_dropped, 6.0, 10.0, 25.0 + 0.75);
}

}  // namespace
}  // namespace poreshell
