#pragma once
// The discrete narrow band of section 2, stored as compact arrays:
//   band voxels  Omega_delta^h = { |psi| < delta |grad_h psi| },  delta = 1.1 sqrt(3) h, and every grid
//                point with |psi| < h (the discrete gradient vanishes across a thin part's middle),
//   ghost points: the grid points outside the band that the band's 7-point Laplacian touches,
//   for each ghost the trilinear stencil (8 band voxels and weights) at its closest point cp(x).
// Ghosts are stored by the parity of i + j + k (even first), then by key, so a red-black sweep
// refreshes the ghosts it reads as one contiguous range.
// Nothing here is sized by Nx*Ny*Nz: memory and time grow with the band.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <optional>
#include <span>
#include <utility>
#include <vector>

#include "core/grid.hpp"
#include "core/run_monitor.hpp"
#include "core/trilinear.hpp"
#include "geometry/surface.hpp"

namespace poreshell {

enum class ClosestPointRule {
  exact,           // the surface's own closest point (falls back to the paper's formula if it has none)
  paper_gradient,  // cp(x) = x - grad_h psi / |grad_h psi|^2 * psi (section 2)
};

struct BandOptions {
  double delta_in_h = 1.1 * 1.7320508075688772;  // delta / h
  ClosestPointRule closest_point = ClosestPointRule::exact;
  StageProgress progress{};  // the build's share of its stage: checked and reported in its long loops
  // The largest |grad_h psi| the scan allows for: only points with |psi| < delta times this can pass the
  // band rule. sqrt(3) bounds it for every 1-Lipschitz psi, which makes the band exact. A preview of a
  // surface with exact closest points takes kLikelyGradientBound: its scan then reaches 3.1 h instead of
  // 4.3 h (a quarter fewer distance queries).
  double gradient_bound = 1.7320508075688772;
  // Only the band voxels that carry surface area (|psi| < h, all of them band voxels) and no ghosts: a
  // layer to lay holes out on, measure them and paint a mesh from, not to solve on (neighbours off the
  // layer are -1). Its voxels, distances and closest points are the band's, so a layout on it is the
  // band's; its scan reaches 1.01 h instead of 3.1-4.3 h. A preview's, where it shows the input mesh.
  bool surface_layer = false;
};

// Over the band voxels of the bunny, Spot, the bunny's points, the sphere and the torus (meshed or at the
// paper's grid, previews included), |psi| / delta was at most 1.042: the band rule found no voxel beyond
// that for a grid-point distance. A scan allowing 1.1 finds the same band on all of them.
constexpr double kLikelyGradientBound = 1.1;

// The trilinear stencil at a ghost's closest point. Corner c = di + 2 dj + 4 dk of the cell is the band
// voxel row[dj + 2 dk] + di: keys are sorted and (i + 1, j, k) has the next key, so the x-neighbour is
// the next band index. 28 bytes instead of 96 for 8 indices and weights: the stencils are streamed on
// every ghost refresh, the solvers' most frequent pass. The fractions are float: the stencil is then exact
// at a point within 2^-24 cells of cp(x), far below the scheme's O(h^2), for 12 bytes less per ghost.
struct GhostStencil {
  std::array<std::int32_t, 4> row{};  // band index of corner (0, dj, dk)
  std::array<float, 3> t{};           // cp's position in its cell, per axis in [0, 1]

  std::int32_t corner(int c) const { return row[c >> 1] + (c & 1); }
  double weight(int c) const { return trilinear_weight(Vec3(t[0], t[1], t[2]), c); }
  template <class T>
  T interpolate(const T* values) const {
    const auto along_x = [&](int r) {
      const T* v = values + row[static_cast<std::size_t>(r)];
      return v[0] + static_cast<T>(t[0]) * (v[1] - v[0]);
    };
    return trilinear_from_rows(along_x, static_cast<T>(t[1]), static_cast<T>(t[2]));
  }
};

struct BandStats {
  std::int64_t candidate_blocks = 0;      // 8^3 blocks the Lipschitz bound could not skip
  std::int64_t paper_ghosts = 0;          // ghosts that satisfy the paper's I|grad_h I| != 0
  std::int64_t closure_added = 0;         // voxels added so that every stencil corner is a band voxel
  double max_closest_point_offset = 0.0;  // max |cp(x) - x| / h over ghosts
};

class NarrowBand {
 public:
  static constexpr int kNeighbors = 6;  // order: -x, +x, -y, +y, -z, +z

  explicit NarrowBand(const Grid& grid) : grid_(grid) {}

  const Grid& grid() const { return grid_; }
  std::size_t size() const { return voxels_.size(); }
  std::size_t ghost_count() const { return ghosts_.size(); }
  // Length of a value array that holds the band followed by its ghosts.
  std::size_t extended_size() const { return voxels_.size() + ghosts_.size(); }

  std::span<const Coord> voxels() const { return voxels_; }
  std::span<const Coord> ghosts() const { return ghosts_; }
  // Signed distance psi at each band voxel, as the surface gave it.
  std::span<const double> distance() const { return distance_; }
  // Surface area carried by band voxel v: h^2 hat(psi / h). The hat's shifts sum to one, so a column of
  // voxels across the surface carries h^2 however the surface sits between grid points (counting voxels
  // instead is off by up to 20% for a flat sheet aligned with the grid).
  double surface_area(std::size_t v) const {
    const double h = grid_.h();
    return h * h * std::max(0.0, 1.0 - std::abs(distance_[v]) / h);
  }
  // cp(x) of each band voxel by the band's closest-point rule, for the multigrid's transfers. Kept as
  // float offsets from the voxel in units of h (12 bytes a voxel; the transfers are float).
  std::vector<Vec3> closest_points() const;
  Vec3 closest_point(std::size_t v) const {
    const auto& o = closest_point_offsets_[v];
    return grid_.position(voxels_[v]) + grid_.h() * Vec3(o[0], o[1], o[2]);
  }
  // Neighbour n of band voxel v: an index into the extended array (< size(): band; else ghost; -1 off
  // a surface layer).
  std::int32_t neighbor(std::size_t v, int n) const { return neighbors_[v * kNeighbors + n]; }
  std::span<const std::int32_t> neighbor_table() const { return neighbors_; }
  std::span<const GhostStencil> stencils() const { return stencils_; }
  const BandStats& stats() const { return stats_; }
  // Built as a surface layer (BandOptions::surface_layer): nothing may be solved on it.
  bool surface_layer() const { return surface_layer_; }

  // Band index of a grid point, or -1 if it is not a band voxel (binary search; build-time use).
  std::int64_t find(const Coord& c) const;
  // The same for c and its +x neighbour, with one search.
  std::array<std::int64_t, 2> find_x_pair(const Coord& c) const;

  // Writes the ghost entries of an extended array from its band entries (closest-point extension).
  void fill_ghosts(std::span<double> extended) const;
  // The same for the ghosts whose i + j + k has this parity (0 or 1) only; float for the multigrid.
  void fill_ghosts(std::span<double> extended, int parity) const;
  void fill_ghosts(std::span<float> extended, int parity) const;
  void fill_ghosts(std::span<float> extended) const;
  // Ghost indices [begin, end) of that parity (0-based among the ghosts).
  std::pair<std::size_t, std::size_t> ghosts_of_parity(int parity) const {
    return parity == 0 ? std::pair<std::size_t, std::size_t>{0, odd_ghosts_begin_}
                       : std::pair<std::size_t, std::size_t>{odd_ghosts_begin_, ghosts_.size()};
  }

  // Approximate heap bytes held by the band arrays.
  std::size_t memory_bytes() const;

 private:
  friend NarrowBand build_band(const Surface&, const Grid&, const BandOptions&);
  friend class BandBuilder;  // build_band's steps (band.cpp)

  Grid grid_;
  std::vector<Coord> voxels_;
  std::vector<std::int64_t> keys_;  // grid keys of voxels_, ascending
  std::vector<double> distance_;
  std::vector<std::array<float, 3>> closest_point_offsets_;
  std::vector<Coord> ghosts_;  // even i + j + k first, then odd; by key within each
  std::size_t odd_ghosts_begin_ = 0;
  std::vector<std::int32_t> neighbors_;
  std::vector<GhostStencil> stencils_;
  BandStats stats_;
  bool surface_layer_ = false;
};

// Closest point on `surface` of x: exact where the rule and the surface allow, else the paper's formula
// cp = x - grad_h psi / |grad_h psi|^2 psi with central differences of step h; nothing where that
// gradient vanishes.
std::optional<Vec3> closest_point_at(const Surface& surface, const Vec3& x, double h, ClosestPointRule rule);
// The same for grid point c (step: the grid's h); throws InputError where the gradient vanishes.
Vec3 closest_point_at(const Surface& surface, const Grid& grid, const Coord& c, ClosestPointRule rule);

// Trilinear interpolation of band values at a point p: the 8 corners of p's cell. Corners that are not
// band voxels (rare near the band's edge: its rule uses the discrete gradient) get weight 0 and the
// others are renormalised; present_weight is their weight before that (1: all there, 0: none).
struct PointStencil {
  std::array<std::int32_t, 8> corner{};  // band indices
  std::array<double, 8> weight{};
  double present_weight = 0.0;
  bool complete = true;  // no corner of nonzero weight was missing
  double interpolate(std::span<const double> values) const {
    double v = 0.0;
    for (int c = 0; c < 8; ++c) v += weight[c] * values[corner[c]];
    return v;
  }
};
PointStencil interpolation_stencil(const NarrowBand& band, const Vec3& p);

// A grid of spacing h around the surface's bounds with room for its band and ghosts on every side.
Grid covering_grid(const Surface& surface, double h);

// Builds the band of `surface` on `grid`. Throws InputError if the band would touch the grid's edge
// or is empty.
NarrowBand build_band(const Surface& surface, const Grid& grid, const BandOptions& options = {});

}  // namespace poreshell
