#pragma once
// The paper's point-cloud route (section 3.4): densify triangular patches by longest-edge bisection
// (Fig. 8), then segment inside from outside with eq. (3.3),
//   d psi/dt = g(x) [ -F'(psi)/eps^2 + Lap psi + lambda F(psi) ],   g(x) = distance to the points,
// on a sparse band of voxels around the points only, and turn the result into a discrete signed
// distance function sampled on the grid's lattice. The band then takes closest points from the paper's
// gradient formula, as in the paper. Parameters and checks: docs/point-clouds.md.

#include <cstdint>
#include <memory>
#include <vector>

#include "core/grid.hpp"
#include "input/patches.hpp"
#include "input/sampled_level_set.hpp"

namespace poreshell {

struct SegmentationOptions {
  double densify_tolerance_in_h = 0.5;  // Fig. 8's tolerance on the edge length
  double band_in_h = 10.0;              // eq. (3.3) is solved where g < band (and the ghost layer beyond)
  double epsilon_in_h = 0.96;           // eps = eps_4 = 4 h / (2 sqrt 2 atanh 0.9), as for the pattern
  double lambda_eps2 = 0.1;             // lambda eps^2: the F(psi) forcing, weak against the double well
  int max_iterations = 20;              // explicit steps of eq. (3.3); longer runs erode thin parts
  double tolerance = 1e-4;              // stop when max |psi^{n+1} - psi^n| < tolerance
  bool cap_holes = true;                // close holes in the patches before segmenting
};

struct SegmentationStats {
  int hole_caps = 0;               // holes closed before densification
  std::int64_t points = 0;         // after densification
  std::int64_t band_voxels = 0;    // where eq. (3.3) is solved
  std::int64_t ghost_voxels = 0;   // Dirichlet layer (psi = +-1) around it
  std::int64_t inside_voxels = 0;  // band voxels seeded inside
  int iterations = 0;
  double dt = 0.0, epsilon = 0.0, lambda = 0.0;
  double last_change = 0.0;  // max |psi^{n+1} - psi^n| at the last step
  std::int64_t zero_level_triangles = 0;
  double zero_level_max_gap = 0.0;  // max distance from the zero level's vertices to the points
};

// Densifies (patches: `triangles`, or umbrellas when empty) and segments the points (in the same
// coordinates as `grid`, whose h sets every length). Throws InputError when the points do not enclose a
// volume at this resolution (holes wider than the band).
std::unique_ptr<SampledLevelSet> segment_point_cloud(const std::vector<Vec3>& points,
                                                     const Triangles& triangles, const Grid& grid,
                                                     const SegmentationOptions& options = {},
                                                     SegmentationStats* stats = nullptr);

}  // namespace poreshell
