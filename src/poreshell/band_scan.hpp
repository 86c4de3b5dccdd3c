#pragma once
// The band builder's one pass over the surface: psi = surface.distance at every grid point within
// `reach` of the surface, and there the closest point too where the surface gives an exact one. Every
// point is queried at most once; the band rule's central differences, the ghosts' stencils, the
// closure's corners and the multigrid's transfers then read these values instead of asking the
// surface again (before, a mesh's tree was searched about 6 times per band voxel).
//
// Storage is by 8^3 blocks of the grid, kept only where a point is within reach: memory grows with the
// surface area times the reach, not with the grid.

#include <array>
#include <cmath>
#include <cstdint>
#include <memory>
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
  // The closest point recorded at c (within reach, on a surface with exact closest points), else null.
  const Vec3* closest_point(const Coord& c) const;

  // Calls f(c, psi) for the points of block b (0 <= b < block_count()) within reach.
  template <class F>
  void for_each_near_point(std::size_t b, const F& f) const {
    const Block* block = blocks_[b].get();
    if (block == nullptr) return;
    for (int s = 0; s < kBlock * kBlock * kBlock; ++s)
      if (!std::isnan(block->psi[static_cast<std::size_t>(s)]))
        f(Coord{block->origin.i + s % kBlock, block->origin.j + (s / kBlock) % kBlock,
                block->origin.k + s / (kBlock * kBlock)},
          block->psi[static_cast<std::size_t>(s)]);
  }
  std::size_t block_count() const { return blocks_.size(); }
  std::int64_t blocks_scanned() const { return blocks_scanned_; }

 private:
  struct Block {
    Coord origin;
    std::array<double, kBlock * kBlock * kBlock> psi;  // NaN: beyond reach
    std::vector<std::uint16_t> slots;                  // near slots with a closest point, ascending
    std::vector<Vec3> closest;                         // one per slot
  };
  const Block* block_of(const Coord& c, int& slot) const;

  Grid grid_;
  std::array<int, 3> blocks_per_axis_{};
  std::vector<std::unique_ptr<Block>> blocks_;  // null: no point within reach (one pointer per block)
  std::int64_t blocks_scanned_ = 0;
};

}  // namespace poreshell
