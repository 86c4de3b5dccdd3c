// poreshell::estimate(): what a run will cost, said before it runs. The band is counted on a coarser
// grid and the rest are fits (docs/benchmarks.md "Estimates"), so these tests hold the estimate to what a
// run then measures, within the fits' stated error, and to the warnings a user needs.

#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <string>

#include "poreshell/poreshell.hpp"
#include "test_meshes.hpp"

using namespace poreshell;

namespace {

Options holes(double diameter, double spacing) {
  Options o;
  o.hole_diameter = diameter;
  o.spacing = spacing;
  o.wall = 2.0;
  return o;
}

bool any_warning_has(const Estimate& e, const std::string& text) {
  return std::any_of(e.warnings.begin(), e.warnings.end(),
                     [&](const std::string& w) { return w.find(text) != std::string::npos; });
}

}  // namespace

// A preview is estimated as what it makes: the band on the pattern's own grid, the surface's slab as
// PLY, and a fraction of the full run's time.
TEST(Estimate, PreviewIsEstimatedAsThePaintedSurfaceAndMatchesTheRun) {
  Options o = holes(6.0, 10.0);
  o.preview = true;
  const Input input = sphere(25.0);
  const Estimate preview = estimate(input, o);
  EXPECT_TRUE(preview.preview);
  const Result r = perforate(input, o);
  const auto voxels = static_cast<double>(r.report.band.voxels);
  EXPECT_NEAR(preview.band_voxels, voxels, 0.15 * voxels);
  const auto triangles = static_cast<double>(r.outputs.at(0).mesh.triangles.size());
  EXPECT_NEAR(preview.triangles, triangles, 0.10 * triangles);
  // The file a preview writes, measured.
  const std::filesystem::path ply =
      std::filesystem::temp_directory_path() / ("poreshell-estimate-" + std::to_string(::getpid()) + ".ply");
  save_mesh(ply, r.outputs.at(0));
  const auto bytes = static_cast<double>(std::filesystem::file_size(ply));
  std::filesystem::remove(ply);
  EXPECT_NEAR(preview.ply_bytes, bytes, 0.15 * bytes);

  o.preview = false;
  o.max_deviation = 0.0;  // the full isosurface
  const Estimate full = estimate(input, o);
  EXPECT_FALSE(full.preview);
  EXPECT_LT(preview.seconds, 0.5 * full.seconds) << "a preview solves nothing";
  EXPECT_GT(full.triangles, preview.triangles) << "the shell is meshed finer than the band";
  EXPECT_EQ(full.ply_bytes, 0.0);
}

// A mesh input's preview is the mesh split down to the band's resolution: the estimate counts those
// triangles exactly, and the PLY's size within its per-triangle fit; its band is the surface layer.
TEST(Estimate, APreviewOfAMeshCountsItsSplitTriangles) {
  MeshInput sleeve;
  sleeve.mesh = test_support::open_sleeve(30.0, 100.0, 24, 2);
  Options o = holes(6.0, 10.0);
  o.preview = true;
  const Estimate e = estimate(sleeve, o);
  const Result r = perforate(sleeve, o);
  const auto triangles = static_cast<double>(r.outputs.at(0).mesh.triangles.size());
  EXPECT_GT(triangles, 100.0 * static_cast<double>(sleeve.mesh.triangles.size()));
  EXPECT_EQ(e.triangles, triangles);
  // The layer is h / delta of the band (here 56,211 of 108,747 voxels); the band's estimate, counted on
  // a grid 8 times coarser, is 21% high on this short open sleeve: its open edges' share of the band
  // grows with the grid's spacing.
  const auto layer = static_cast<double>(r.report.band.voxels);
  EXPECT_NEAR(e.band_voxels, layer, 0.25 * layer);
  EXPECT_EQ(r.report.band.ghosts, 0) << "a layer to look at, not to solve on";
  const std::filesystem::path ply = std::filesystem::temp_directory_path() /
                                    ("poreshell-estimate-mesh-" + std::to_string(::getpid()) + ".ply");
  save_mesh(ply, r.outputs.at(0));
  const auto bytes = static_cast<double>(std::filesystem::file_size(ply));
  std::filesystem::remove(ply);
  EXPECT_NEAR(e.ply_bytes, bytes, 0.15 * bytes);
}

// A scan in metres read as millimetres is a speck: the estimate says so and names the unit that makes
// it a usual size.
TEST(Estimate, ATinyModelGetsTheUnitThatMakesItAUsualSize) {
  MeshInput scan;  // a tetrahedron 0.15 across: metres, given as mm
  scan.mesh.vertices = {{0, 0, 0}, {0.15, 0, 0}, {0, 0.15, 0}, {0, 0, 0.15}};
  scan.mesh.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  const Estimate e = estimate(scan, Options{});
  EXPECT_TRUE(any_warning_has(e, "smaller than most prints")) << (e.warnings.empty() ? "" : e.warnings[0]);
  EXPECT_TRUE(any_warning_has(e, "`units` m")) << (e.warnings.empty() ? "" : e.warnings[0]);
  scan.unit = Unit::m;
  EXPECT_FALSE(any_warning_has(estimate(scan, Options{}), "than most prints"));
}

// `max_triangles` caps the output but costs a collapse per two triangles removed and the reduction's
// structures: a big shell reduced hard is a long run, and the estimate warns before it starts.
TEST(Estimate, AReductionAddsItsTimeAndMemory) {
  const Input input = sphere(400.0);  // about 84 million triangles meshed
  Options o = holes(6.0, 10.0);
  const Estimate bounded = estimate(input, o);  // the default: reduced as far as 0.02 mm allows
  o.max_deviation = 0.0;
  const Estimate whole = estimate(input, o);
  EXPECT_LT(bounded.triangles, 0.5 * whole.triangles);
  EXPECT_GT(bounded.peak_bytes, whole.peak_bytes + 100.0 * whole.triangles);
  EXPECT_GT(bounded.seconds, whole.seconds);
  o.max_deviation = 0.05;
  o.max_triangles = 100000;
  const Estimate reduced = estimate(input, o);
  EXPECT_EQ(reduced.triangles, 100000.0);
  EXPECT_LT(reduced.stl_bytes, whole.stl_bytes);
  // 84 M triangles held by the decimater: gigabytes, not the band's hundreds of megabytes; and the
  // collapses' time, at least 6 us for each (two triangles; the calibration machine's 2 cores take
  // about 7, docs/benchmarks.md "Estimates").
  EXPECT_GT(reduced.peak_bytes, whole.peak_bytes + 100.0 * whole.triangles);
  EXPECT_GT(reduced.seconds, whole.seconds + 3e-6 * whole.triangles);
  EXPECT_FALSE(any_warning_has(whole, "minutes"))
      << "the unreduced run is estimated at " << whole.seconds << " s";
  EXPECT_TRUE(any_warning_has(reduced, "minutes"))
      << "the reduced run is estimated at " << reduced.seconds << " s";
}

// prepare(): placed once, it gives estimate() and perforate() what they would find from the input and
// options themselves (a preview and a full run with a rim), so a front end that estimates first does
// not place the input twice; one not made by prepare() is refused.
TEST(Estimate, APreparedInputGivesTheSameEstimateAndTheSameRun) {
  MeshInput sleeve;
  sleeve.mesh = test_support::open_sleeve(30.0, 100.0, 24, 2);
  for (const bool preview : {true, false}) {
    Options o = holes(6.0, 10.0);
    o.preview = preview;
    o.rim = 3.0;
    o.wall = 4.0;           // a quarter of a 2 mm wall's triangles, and the full isosurface (the reduction is
    o.max_deviation = 0.0;  // tested on its own): under ASan this test took 101 s, then 122 s
    const Prepared prepared = prepare(sleeve, o);
    const Estimate a = estimate(prepared), b = estimate(sleeve, o);
    EXPECT_EQ(a.size_mm, b.size_mm);
    EXPECT_EQ(a.grid, b.grid);
    EXPECT_EQ(a.band_voxels, b.band_voxels);
    EXPECT_EQ(a.seconds, b.seconds);
    EXPECT_EQ(a.triangles, b.triangles);
    EXPECT_EQ(a.warnings, b.warnings);
    const Result x = perforate(prepared), y = perforate(sleeve, o);
    ASSERT_EQ(x.outputs.size(), y.outputs.size());
    for (std::size_t i = 0; i < x.outputs.size(); ++i) {
      EXPECT_EQ(x.outputs[i].mesh.vertices, y.outputs[i].mesh.vertices) << "preview " << preview;
      EXPECT_EQ(x.outputs[i].mesh.triangles, y.outputs[i].mesh.triangles) << "preview " << preview;
      EXPECT_EQ(x.outputs[i].holes.size(), y.outputs[i].holes.size());
    }
    EXPECT_EQ(x.report.input.thin_vertices, y.report.input.thin_vertices);
    EXPECT_EQ(x.report.input.crease_edges, y.report.input.crease_edges);
    EXPECT_GT(x.report.seconds.input, 0.0);
  }
  EXPECT_THROW(perforate(Prepared{}), Error);
  EXPECT_THROW(estimate(Prepared{}), Error);
}
