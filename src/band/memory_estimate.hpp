#pragma once
// The band's size before it is built, for refusing runs that would not fit in memory.

#include "core/types.hpp"
#include "geometry/surface.hpp"

namespace poreshell {

// Peak bytes of a whole run per band voxel, measured over the bunny scaling series (docs/benchmarks.md:
// 1.1-1.5 kB, the shell and its mesh included).
inline constexpr double kPeakBytesPerBandVoxel = 1300.0;

struct BandEstimate {
  double voxels = 0.0;      // band voxels on the fine grid (0: no estimate, the run is small)
  double peak_bytes = 0.0;  // of the whole run
};

// Counts the band on a grid 8 times coarser (cheap: 1/64 of the voxels) and scales by (h_coarse / h)^2,
// since a surface's band grows like its area over h^2.
BandEstimate estimate_band(const Surface& surface, const Box& domain, int resolution);

// Refuses, before anything large is allocated, a run whose estimate exceeds `limit_gb` (0: the memory
// available now). Throws Error(too_large) naming the resolution, voxel size or hole size that would fit.
void check_band_fits(const Surface& surface, const Box& domain, int resolution, double limit_gb, double h_mm,
                     bool holes_in_mm);

}  // namespace poreshell
