#pragma once
// The band's size before it is built, and the memory a run may take: what the run's cost (pipeline/
// run_cost.hpp) is held against.

#include "core/types.hpp"
#include "geometry/surface.hpp"

namespace poreshell {

// The band's voxels on the fine grid, counted on a grid 8 times coarser (cheap: 1/64 of the voxels) and
// scaled by (h_coarse / h)^2, since a surface's band grows like its area over h^2; 0 where the run is too
// small for that (or the coarse grid has no band): no estimate.
double estimate_band_voxels(const Surface& surface, const Box& domain, int resolution);

// How much memory a run may take: `limit_gb` where it is given (> 0), else the memory available now, or
// what is left under RLIMIT_AS (ulimit -v) where that is less; and where the figure comes from, in words.
struct MemoryLimit {
  double bytes = 0.0;
  const char* source = "";
};
MemoryLimit memory_limit(double limit_gb);

}  // namespace poreshell
