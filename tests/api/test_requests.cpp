// Requests that cannot be met say so (issue 47, item 6): holes that fit nowhere are refused before the
// run, naming `units` where another unit would make the model a print's size; a layout that places no
// hole is refused rather than writing a part without holes; a keep-out that misses the model and a wall
// thinner than printers make are warned of in the estimate.

#include <gtest/gtest.h>

#include <algorithm>
#include <string>

#include "poreshell/poreshell.hpp"
#include "test_meshes.hpp"

using namespace poreshell;

namespace {

bool any_warning_has(const Estimate& e, const std::string& text) {
  return std::any_of(e.warnings.begin(), e.warnings.end(),
                     [&](const std::string& w) { return w.find(text) != std::string::npos; });
}

// The message of the Error `run` throws, or "" if it throws none.
template <class Run>
std::string error_of(Run run) {
  try {
    run();
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

MeshInput tetrahedron(double size) {
  MeshInput in;
  in.mesh.vertices = {{0, 0, 0}, {size, 0, 0}, {0, size, 0}, {0, 0, size}};
  in.mesh.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  return in;
}

TEST(Requests, HolesWiderThanTheModelAreRefusedNamingTheUnitThatFits) {
  Options o;
  o.hole_diameter = 8.0;
  // The bunny's metres read as millimetres: 0.15 mm across.
  const std::string metres = error_of([&] { perforate(tetrahedron(0.15), o); });
  EXPECT_NE(metres.find("fit nowhere"), std::string::npos) << metres;
  EXPECT_NE(metres.find("say `units` m (it is then 150 mm across)"), std::string::npos) << metres;
  // A 70 mm part and 100 mm holes: no unit helps.
  o.hole_diameter = 100.0;
  const std::string wide = error_of([&] { perforate(tetrahedron(70.0), o); });
  EXPECT_NE(wide.find("holes of 100 mm fit nowhere"), std::string::npos) << wide;
  EXPECT_EQ(wide.find("`units`"), std::string::npos) << wide;
  EXPECT_NE(wide.find("ask for `hole_diameter` well under 70 mm"), std::string::npos) << wide;
}

TEST(Requests, ALayoutThatPlacesNoHoleIsRefused) {
  MeshInput sleeve;
  sleeve.mesh = test_support::open_sleeve(15.0, 20.0, 48, 8);
  Options o;
  // Under the sleeve's 20 mm length, but no centre is a pore's radius from both open edges.
  o.hole_diameter = 19.0;
  o.threads = 2;
  const std::string message = error_of([&] { perforate(sleeve, o); });
  EXPECT_NE(message.find("no hole of 19 mm"), std::string::npos) << message;
  EXPECT_NE(message.find("ask for smaller `hole_diameter`"), std::string::npos) << message;
}

TEST(Requests, AKeepOutThatMissesTheModelIsWarnedOf) {
  Options o;
  o.resolution = 41;
  o.keep_out = {{{460.0, 0.0, 0.0}, 5.0}};
  o.keep_out_boxes = {{{300.0, 300.0, 300.0}, {310.0, 310.0, 310.0}}};
  const Estimate far = estimate(sphere(20.0), o);
  EXPECT_TRUE(any_warning_has(far, "`keep_out` 460,0,0,5 lies 435 mm outside"));
  EXPECT_TRUE(any_warning_has(far, "`keep_out_boxes` 300,300,300,310,310,310 lies"));
  o.keep_out = {{{20.0, 0.0, 0.0}, 5.0}};
  o.keep_out_boxes = {{{-5.0, -5.0, 15.0}, {5.0, 5.0, 25.0}}};
  const Estimate near = estimate(sphere(20.0), o);
  EXPECT_FALSE(any_warning_has(near, "keeps nothing solid"));
}

TEST(Requests, AWallThinnerThanPrintersMakeIsWarnedOf) {
  Options o;
  o.resolution = 41;
  o.wall = 0.2;
  EXPECT_TRUE(any_warning_has(estimate(sphere(20.0), o), "a `wall` of 0.2 mm is thinner than most printers"));
  o.wall = 1.0;
  EXPECT_FALSE(any_warning_has(estimate(sphere(20.0), o), "thinner than most printers"));
}

// Numbers in messages are rounded to what matters (issue 47, item 8): "5080 mm", not "5.08e+03 mm";
// "2.5 times", not "2.441406 times", and rounded up so that following the advice works.
TEST(Requests, MessagesGiveNumbersAsAPersonReadsThem) {
  Options o;
  o.resolution = 33;
  const Estimate large = estimate(tetrahedron(5080.0), o);
  EXPECT_TRUE(any_warning_has(large, "the model is 5080 mm across")) << large.warnings.front();
  for (const std::string& w : large.warnings) EXPECT_EQ(w.find("e+0"), std::string::npos) << w;

  Options tiny;
  tiny.hole_diameter = 0.5;  // 1000 mm at the hole map's voxel size needs about 5000 grid points
  const std::string message = error_of([&] { prepare(tetrahedron(1000.0), tiny); });
  const std::size_t at = message.find(" times larger");
  ASSERT_NE(at, std::string::npos) << message;
  const std::string factor =
      message.substr(message.rfind(' ', at - 1) + 1, at - message.rfind(' ', at - 1) - 1);
  EXPECT_LE(factor.size(), 4u) << message;  // "2.5", not "2.441406"
  tiny.hole_diameter *= std::stod(factor);
  tiny.spacing = 0.0;
  EXPECT_EQ(error_of([&] { prepare(tetrahedron(1000.0), tiny); }).find("times larger"), std::string::npos)
      << "following the advice works";
}

}  // namespace
