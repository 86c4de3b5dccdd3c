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

#include <array>
#include <cstdint>
#include <vector>

#include "poreshell/grid.hpp"
#include "poreshell/surface.hpp"

namespace poreshell {

class NearField {
 public:
  static constexpr int kBlock = 8;

  NearField(const Surface& surface, const Grid& grid, double reach);

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
