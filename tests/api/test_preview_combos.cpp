// A preview of a mesh input, over every way it can choose its pattern and both solvers (issue 47): the
// paper's parameters and `layout paper` run the equation, which needs the whole band; only the even
// layout's discs as placed may use the band's surface layer. Solving on the layer wrote past its arrays
// (a segfault with the fast solver, "free(): invalid next size" with the reference one).

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "poreshell/poreshell.hpp"
#include "test_meshes.hpp"

using namespace poreshell;

namespace {

struct Combo {
  std::string name;
  SolverKind solver;
  bool holes_in_mm;
  Layout layout;
  bool runs_equation;
};

Options combo_options(const Combo& c) {
  Options o;
  o.preview = true;
  o.solver = c.solver;
  o.layout = c.layout;
  o.max_steps = 2;  // a few steps: the crash came at the solver's set-up
  o.threads = 2;
  if (c.holes_in_mm) {
    o.hole_diameter = 8.0;
    o.spacing = 13.0;
  } else {
    o.resolution = 33;
  }
  return o;
}

TEST(PreviewCombos, AMeshPreviewGivesAPatternOnTheMeshWhateverItsLayoutAndSolver) {
  MeshInput sleeve;
  sleeve.mesh = test_support::open_sleeve(15.0, 30.0, 24, 4);
  sleeve.name = "sleeve";
  const Combo combos[] = {
      {"paper's parameters, fast", SolverKind::fast, false, Layout::automatic, true},
      {"paper's parameters, reference", SolverKind::reference, false, Layout::automatic, true},
      {"holes in mm, layout paper, fast", SolverKind::fast, true, Layout::paper, true},
      {"holes in mm, layout paper, reference", SolverKind::reference, true, Layout::paper, true},
      {"holes in mm, even layout, fast", SolverKind::fast, true, Layout::automatic, false},
      {"holes in mm, even layout, reference", SolverKind::reference, true, Layout::automatic, false},
  };
  for (const Combo& c : combos) {
    SCOPED_TRACE(c.name);
    const Options o = combo_options(c);
    const Estimate e = estimate(sleeve, o);
    const Result r = perforate(sleeve, o);
    ASSERT_TRUE(r.report.preview);
    ASSERT_EQ(r.outputs.size(), 1u);
    const Output& out = r.outputs.front();
    // The input's own triangles, split down to the band's resolution, with phi at each vertex.
    EXPECT_GE(out.mesh.triangles.size(), sleeve.mesh.triangles.size());
    ASSERT_EQ(out.pattern.size(), out.mesh.vertices.size());
    for (const double phi : out.pattern) ASSERT_TRUE(std::isfinite(phi));
    EXPECT_EQ(r.report.solver.steps > 0, c.runs_equation);
    EXPECT_GT(r.report.band.voxels, 0);
    EXPECT_EQ(e.triangles, static_cast<double>(out.mesh.triangles.size()));
  }
}

}  // namespace
