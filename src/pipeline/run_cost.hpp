#pragma once
// A run's cost before it runs: its band, time, peak memory and output, from the input as the run will
// place it. One model for the estimate that estimate() prints and for the guard that refuses a run that
// would not fit (issue 47: the printout said 863 MiB where the guard refused at 4.03 GB, and neither
// counted the input's own structures).

#include "pipeline/pipeline.hpp"

namespace poreshell {

struct RunCost {
  double band_voxels = 0.0;  // 0 where the run is too small to estimate on a coarser grid
  double seconds = 0.0;      // the whole run, 2 threads of the calibration machine
  double peak_bytes = 0.0;   // resident memory, the input's structures included
  double fixed_bytes = 0.0;  // the part of peak_bytes that no grid changes: the program and the input
  double triangles = 0.0;    // per output level
  double stl_bytes = 0.0;    // per output level as binary STL
  double ply_bytes = 0.0;    // a preview's output as PLY with vertex colours
  double voxel_size_mm = 0.0;
  double shell_mm = 0.0;  // the shell grid's spacing (what the wall is meshed at)
};

// The wall the run builds, in mm, and where it comes from: "asked" (`wall`), "default" (kDefaultWallMm for
// holes asked in mm, shell mode) or "band" (the band's width 2 delta: the paper's parameters, the narrow
// volume). One rule for the run and its estimate.
struct WallChoice {
  double mm = 0.0;
  const char* source = "";
};
WallChoice choose_wall(const Options& options, bool asked_in_mm, double voxel_size_mm);

// `for_printout`: every figure, a run too small for the coarse count building its own band to count
// it; else only what the guard reads, a small run's cost left at 0 (small runs fit).
RunCost estimate_run_cost(const PreparedInput& prepared, bool for_printout);

// Refuses, before anything large is allocated, a run whose cost exceeds `Options::max_memory_gb` (0: the
// memory available now, or what is left under RLIMIT_AS where that is less). Throws Error(too_large)
// with the same figure the estimate prints and the resolution, voxel size or hole size that would fit.
void check_run_fits(const RunCost& cost, const PreparedInput& prepared);

}  // namespace poreshell
