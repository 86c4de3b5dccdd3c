#pragma once
// The paper's point-cloud route (section 3.4): densify triangular patches by longest-edge bisection
// (Fig. 8), then segment inside from outside with eq. (3.3),
//   d psi/dt = g(x) [ -F'(psi)/eps^2 + Lap psi + lambda F(psi) ],   g(x) = distance to the points,
// on a sparse band of voxels around the points only, and turn the result into a discrete signed
// distance function sampled on the grid's lattice. The band then takes closest points from the paper's
// gradient formula, as in the paper. Parameters and checks: docs/point-clouds.md.

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "core/grid.hpp"
#include "geometry/mesh.hpp"
#include "geometry/mesh_surface.hpp"
#include "geometry/point_tree.hpp"
#include "geometry/surface.hpp"

namespace poreshell {

using Triangles = std::vector<std::array<std::int32_t, 3>>;

// Fig. 8: splits each triangle's longest edge at its midpoint until every edge is shorter than
// `tolerance`. Returns the input points followed by the new ones, exact duplicates removed (a shared
// edge is split at the same midpoint from both sides). Throws InputError past `max_points`.
std::vector<Vec3> densify_patches(const std::vector<Vec3>& points, const Triangles& triangles,
                                  double tolerance, std::size_t max_points = 50'000'000);

// Patches for raw points, which have none: each point's umbrella, the triangles between it and
// consecutive nearest neighbours ordered by angle in its tangent plane (PCA), leaving out gaps wider
// than 120 degrees (borders). Duplicates removed.
// Marks in `boundary` the points with such a gap.
Triangles umbrella_patches(const std::vector<Vec3>& points, std::vector<char>* boundary = nullptr,
                           int neighbors = 8);

// Vertices on edges that only one triangle uses.
std::vector<char> boundary_vertices(std::size_t points, const Triangles& triangles);

// Closes holes, which the segmentation cannot tell from the outside: boundary points closer than five
// sample spacings form a rim; each rim of at least `min_points` gets a fan of triangles from its
// centroid (appended to `points`) over the rim ordered by angle in its best-fit plane. Returns the
// number of caps. Not in the paper, which assumes a closed surface.
int cap_holes(std::vector<Vec3>& points, Triangles& triangles, const std::vector<char>& boundary,
              std::size_t min_points);

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

// The discrete signed distance: samples on the lattice x = origin + h (i, j, k), which holds the paper's
// grid's points, so the band there reads psi and takes closest points from the paper's formula. Off the
// lattice (block centres, the fast solver's coarse grids) and beyond the samples: the unsigned distance
// to the zero level, as the mesh route gives, 1-Lipschitz. Without a zero level: trilinear between
// samples, and beyond them a lower bound of |distance| (distance to the points minus the zero level's
// largest gap to them), so the band builder's block culling stays safe.
class SampledLevelSet final : public Surface {
 public:
  SampledLevelSet(const Grid& lattice, std::vector<std::int64_t> keys, std::vector<double> values,
                  std::vector<Vec3> points, double gap, const TriangleMesh* zero_level = nullptr);

  double distance(const Vec3& p) const override;
  // Nothing (the band uses the paper's formula) at lattice points where the central-difference gradient
  // has unit length within 10%, i.e. where the samples are a distance function. Elsewhere (the kink of
  // the distance on the mid-surface of parts thinner than the band, where |grad psi| -> 0 sends the
  // formula's cp far away; points off the lattice) the exact closest point on the zero level.
  std::optional<Vec3> closest_point(const Vec3& p) const override;
  Box bounds() const override;
  std::string name() const override { return "segmented point cloud"; }

  const Grid& lattice() const { return lattice_; }
  std::size_t samples() const { return keys_.size(); }
  // The sample at lattice point c, if there is one.
  std::optional<double> sample(const Coord& c) const;

 private:
  Grid lattice_;
  std::vector<std::int64_t> keys_;  // ascending lattice keys
  std::vector<double> values_;
  std::vector<Vec3> points_;
  PointTree tree_;
  double gap_;
  std::unique_ptr<MeshSurface> zero_level_;
};

// Densifies (patches: `triangles`, or umbrellas when empty) and segments the points (in the same
// coordinates as `grid`, whose h sets every length). Throws InputError when the points do not enclose a
// volume at this resolution (holes wider than the band).
std::unique_ptr<SampledLevelSet> segment_point_cloud(const std::vector<Vec3>& points,
                                                     const Triangles& triangles, const Grid& grid,
                                                     const SegmentationOptions& options = {},
                                                     SegmentationStats* stats = nullptr);

}  // namespace poreshell
