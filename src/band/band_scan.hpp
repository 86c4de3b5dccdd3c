#pragma once
// The band builder's one pass over the surface: psi = surface.distance at every grid point within
// `reach` of the surface, and there the closest point too where the surface gives an exact one. Every
// point is queried at most once; the band rule's central differences, the ghosts' stencils, the
// closure's corners and the voxels' closest points then read these values instead of asking the
// surface again (before, a mesh's tree was searched about 6.5 times per band voxel).
//
// Storage: the points within reach of each 8^3 block of the grid, found through a bit mask per block,
// in one array per row of blocks along x (one allocation per block made the allocator keep megabytes
// after the band was built). Memory grows with the surface area times the reach.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "core/grid.hpp"
#include "core/run_monitor.hpp"
#include "geometry/surface.hpp"

namespace poreshell {

// Calls visit(c) for the grid points c of the block [origin, origin + size)^3 (size a power of 2) that
// may lie within `reach` of the surface, by its distance, which is 1-Lipschitz: one query at a block's
// centre rules out the whole block, or shows all of it within reach, where splitting it further would
// only add queries; grazed blocks are split down to 2^3. visit makes the exact test and returns the
// unsigned distance it found, which skips the next points of the row that are as surely out of reach.
// Returns false when the centre query ruled out the whole block.
template <class Visit>
bool for_each_point_near(const Surface& surface, const Grid& grid, const Coord& origin, int size,
                         double reach, const Visit& visit) {
  constexpr int kSmallestBlock = 2;
  const auto& d = grid.dims();
  if (origin.i >= d[0] || origin.j >= d[1] || origin.k >= d[2]) return false;
  const double h = grid.h();
  const Vec3 center = grid.position(origin) + Vec3::Constant(0.5 * (size - 1) * h);
  const double half_diagonal = 0.5 * std::sqrt(3.0) * (size - 1) * h;
  const double center_distance = std::abs(surface.distance_up_to(center, reach + half_diagonal));
  if (center_distance > reach + half_diagonal) return false;
  if (size > kSmallestBlock && center_distance + half_diagonal > reach) {
    const int half = size / 2;
    for (int c = 0; c < 8; ++c)
      for_each_point_near(
          surface, grid,
          {origin.i + (c & 1) * half, origin.j + ((c >> 1) & 1) * half, origin.k + (c >> 2) * half}, half,
          reach, visit);
    return true;
  }
  for (int k = origin.k; k < std::min(origin.k + size, d[2]); ++k)
    for (int j = origin.j; j < std::min(origin.j + size, d[1]); ++j)
      for (int i = origin.i; i < std::min(origin.i + size, d[0]); ++i) {
        const double distance = visit(Coord{i, j, k});
        if (distance > reach && std::isfinite(distance))
          i += static_cast<int>(std::floor((distance - reach) / h));
      }
  return true;
}

class NearField {
 public:
  static constexpr int kBlock = 8;

  NearField(const Surface& surface, const Grid& grid, double reach, const StageProgress& progress = {});

  // psi at c, or NaN where c is beyond reach or outside the grid.
  double psi(const Coord& c) const;
  // Whether closest points were recorded (surfaces with exact ones), and the one at c (within reach).
  bool has_closest_points() const { return exact_; }
  Vec3 closest_point(const Coord& c) const;

  // Calls f(c, psi) for the points within reach in row r of blocks (0 <= r < row_count()), block by
  // block; rows may run in parallel.
  template <class F>
  void for_each_near_point(std::size_t r, const F& f) const;
  std::size_t row_count() const { return rows_.size(); }
  std::int64_t blocks_scanned() const { return blocks_scanned_; }

 private:
  static constexpr int kSlots = kBlock * kBlock * kBlock;
  struct BlockEntry {
    Coord origin;
    std::array<std::uint64_t, kSlots / 64> mask{};  // slots within reach
    std::uint32_t first = 0;                        // its first point in the row's arrays
  };
  struct Row {
    std::vector<BlockEntry> blocks;
    std::vector<double> psi;    // by block, then slot
    std::vector<Vec3> closest;  // where exact_ (double: the ghosts' stencils use them)
  };
  // The row and point index of c, or false if c is not within reach.
  bool locate(const Coord& c, const Row*& row, std::size_t& point) const;

  Grid grid_;
  bool exact_ = false;
  std::array<int, 3> blocks_per_axis_{};
  std::vector<std::int32_t> block_entry_;  // per block of the grid: index in its row's blocks, or -1
  std::vector<Row> rows_;                  // row bj + (blocks along y) * bk
  std::int64_t blocks_scanned_ = 0;
};

template <class F>
void NearField::for_each_near_point(std::size_t r, const F& f) const {
  const Row& row = rows_[r];
  for (const BlockEntry& block : row.blocks) {
    std::size_t point = block.first;
    for (int s = 0; s < kSlots; ++s)
      if ((block.mask[static_cast<std::size_t>(s / 64)] >> (s % 64)) & 1)
        f(Coord{block.origin.i + s % kBlock, block.origin.j + (s / kBlock) % kBlock,
                block.origin.k + s / (kBlock * kBlock)},
          row.psi[point++]);
  }
}

}  // namespace poreshell
