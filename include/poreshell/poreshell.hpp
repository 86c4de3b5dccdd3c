#pragma once
// poreshell: uniform round pores on any surface, as one printable part.
//
//   #include <poreshell/poreshell.hpp>
//   poreshell::Options options;
//   options.hole_diameter = 8;  // mm
//   options.spacing = 14;
//   options.wall = 2;
//   poreshell::Result r = poreshell::perforate(poreshell::load_mesh("bunny.obj", poreshell::Unit::m),
//   options); poreshell::save_mesh("bunny.stl", r.outputs[0].mesh);
//
// The method is the nonlocal Cahn-Hilliard equation on a narrow band of voxels around the surface,
// with closest-point ghost values (docs/method.md).

#include <memory>

#include "poreshell/error.hpp"
#include "poreshell/export.hpp"
#include "poreshell/geometry.hpp"
#include "poreshell/io.hpp"
#include "poreshell/options.hpp"
#include "poreshell/progress.hpp"
#include "poreshell/result.hpp"
#include "poreshell/viewer.hpp"

namespace poreshell {

// Runs the whole job in memory: the pattern on the surface, the printable solid, its checks and its
// holes. Throws Error; writes nothing. Safe to call from several threads at once: each run has its own
// state, and the same input and options give the same bytes whatever else runs and whatever the
// thread count.
PORESHELL_API Result perforate(const Input& input, const Options& options, const RunControl& control = {});

// What a run would cost, before running it: the model's size, the band, the time, the peak memory and
// the output's size, and warnings worth reading first (a size that suggests a wrong unit, holes too
// large for the model, a long run, a large output). Options are named in backquotes, as in Error. The
// time, memory and output size are fitted to runs on one machine (docs/benchmarks.md, "Estimates",
// gives the fits and their errors). Costs about what a run's input stage costs plus a band on a grid 8
// times coarser. Throws Error as perforate() would.
struct Estimate {
  Point size_mm{};  // the model's bounding box, mm (with Options::scale)
  std::array<int, 3> grid{};
  double voxel_size_mm = 0.0;
  double band_voxels = 0.0;
  double seconds = 0.0;     // the whole run, 2 threads of the calibration machine
  double peak_bytes = 0.0;  // resident memory
  double triangles = 0.0;   // per output level
  double stl_bytes = 0.0;   // per output level as binary STL
  bool preview = false;     // Options::preview: the output is the surface painted, not a shell
  double ply_bytes = 0.0;   // a preview's output as PLY with vertex colours (its usual format)
  std::vector<std::string> warnings;
};
PORESHELL_API Estimate estimate(const Input& input, const Options& options);

// The work that estimate() and perforate() both begin with, done once: the options checked and the
// input placed on its grid with its search structures built (a tenth of a second for a 70k-triangle
// scan, seconds for millions of triangles). A caller that estimates before it runs prepares once and
// passes the result to both; the answers are the same as from the input and options. It keeps a copy
// of the options and a pointer to the input, which must outlive it. Throws Error as perforate() would.
namespace detail {
struct PreparedInput;
}
struct Prepared {
  const Input* input = nullptr;
  std::shared_ptr<const detail::PreparedInput> state;  // opaque
};
PORESHELL_API Prepared prepare(const Input& input, const Options& options);
PORESHELL_API Estimate estimate(const Prepared& prepared);
PORESHELL_API Result perforate(const Prepared& prepared, const RunControl& control = {});

PORESHELL_API const char* version();

}  // namespace poreshell
