// The report's "applied" figures: the rim left along the open boundary and the keep-outs' clearance,
// measured from hole discs against a flat 100 x 60 mm sheet (boundary: its four edges).

#include <gtest/gtest.h>

#include <cmath>

#include "input/placement.hpp"
#include "shell/zone_check.hpp"

namespace poreshell {
namespace {

PlacedSurface flat_sheet() {
  MeshInput input;
  const int nx = 10, ny = 6;  // 10 mm squares
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i) input.mesh.vertices.push_back({10.0 * i, 10.0 * j, 0.0});
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const int a = j * (nx + 1) + i, b = a + 1, c = a + nx + 1, d = c + 1;
      input.mesh.triangles.push_back({a, b, d});
      input.mesh.triangles.push_back({a, d, c});
    }
  PlacementOptions options;
  options.resolution = 65;
  options.scale = 1.0;
  return place_surface(input, options);
}

TEST(ZoneCheck, RimIsTheLeastDistanceFromAHoleEdgeToTheBoundary) {
  const PlacedSurface sheet = flat_sheet();
  // Nearest edges: the first disc is 12 mm from x = 0 (edge 10 mm away), the second 9 mm from y = 60.
  const std::vector<HoleDisc> holes{{{12.0, 30.0, 0.0}, 4.0}, {{50.0, 51.0, 0.0}, 6.0}};
  const ZoneCheck check = check_zones(holes, ZoneOptions{}, sheet);
  EXPECT_NEAR(check.rim, 6.0, 1e-9);  // 9 - 3
  EXPECT_TRUE(std::isnan(check.keep_out_clearance));
  EXPECT_EQ(check.holes_in_keep_outs, 0);
}

TEST(ZoneCheck, KeepOutsCountTheHolesThatReachIn) {
  const PlacedSurface sheet = flat_sheet();
  ZoneOptions options;
  options.keep_out.push_back({Vec3(30.0, 30.0, 0.0), 5.0});
  options.keep_out_boxes.push_back(SolidBox::spanned({70.0, 0.0, -1.0}, {60.0, 20.0, 1.0}));
  const std::vector<HoleDisc> holes{
      {{40.0, 30.0, 0.0}, 4.0},  // 10 from the sphere's centre: its edge 3 mm clear
      {{65.0, 25.0, 0.0}, 6.0},  // 5 mm above the box, radius 3: 2 mm clear
      {{65.0, 21.0, 0.0}, 4.0},  // 1 mm above the box, radius 2: reaches 1 mm in
  };
  const ZoneCheck check = check_zones(holes, options, sheet);
  EXPECT_EQ(check.holes_in_keep_outs, 1);
  EXPECT_NEAR(check.keep_out_clearance, -1.0, 1e-9);
  const ZoneCheck clear = check_zones(std::span(holes).first(2), options, sheet);
  EXPECT_EQ(clear.holes_in_keep_outs, 0);
  EXPECT_NEAR(clear.keep_out_clearance, 2.0, 1e-9);
}

TEST(ZoneCheck, NoHolesOrNoBoundaryGiveNaN) {
  const PlacedSurface sheet = flat_sheet();
  EXPECT_TRUE(std::isnan(check_zones({}, ZoneOptions{}, sheet).rim));
  PlacementOptions grid;
  grid.resolution = 65;
  grid.scale = 1.0;
  PlacedSurface shape = place_surface(ShapeInput{ShapeKind::sphere, 20.0, Unit::mm}, grid);
  const std::vector<HoleDisc> holes{{{0.0, 0.0, 20.0}, 4.0}};
  EXPECT_TRUE(std::isnan(check_zones(holes, ZoneOptions{}, shape).rim));
}

}  // namespace
}  // namespace poreshell
