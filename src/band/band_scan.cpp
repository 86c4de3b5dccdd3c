#include "band/band_scan.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <optional>

#include "core/parallel.hpp"

namespace poreshell {

NearField::NearField(const Surface& surface, const Grid& grid, double reach, const StageProgress& progress)
    : grid_(grid), exact_(surface.closest_point_is_exact()) {
  const auto& d = grid.dims();
  for (std::size_t a = 0; a < 3; ++a) blocks_per_axis_[a] = (d[a] + kBlock - 1) / kBlock;
  block_entry_.assign(static_cast<std::size_t>(blocks_per_axis_[0]) *
                          static_cast<std::size_t>(blocks_per_axis_[1]) *
                          static_cast<std::size_t>(blocks_per_axis_[2]),
                      -1);
  rows_.resize(static_cast<std::size_t>(blocks_per_axis_[1]) * static_cast<std::size_t>(blocks_per_axis_[2]));
  std::vector<std::int64_t> scanned(rows_.size(), 0);
  monitored_for(rows_.size(), progress, [&](std::size_t r) {
    Row& row = rows_[r];
    const auto bj = static_cast<int>(r % static_cast<std::size_t>(blocks_per_axis_[1]));
    const auto bk = static_cast<int>(r / static_cast<std::size_t>(blocks_per_axis_[1]));
    std::array<double, kSlots> psi;
    std::array<Vec3, kSlots> closest;
    // The last closest point found in this row: the next point's is near it (rows are scanned in order,
    // so the results do not depend on the threads).
    std::optional<Vec3> last;
    for (int bi = 0; bi < blocks_per_axis_[0]; ++bi) {
      const Coord origin{bi * kBlock, bj * kBlock, bk * kBlock};
      BlockEntry entry;
      entry.origin = origin;
      psi.fill(std::numeric_limits<double>::quiet_NaN());
      const bool near = for_each_point_near(surface, grid, origin, kBlock, reach, [&](const Coord& c) {
        const Vec3 x = grid.position(c);
        SurfaceQuery q;
        if (exact_) {
          q = last ? surface.distance_and_closest_point_near(x, *last)
                   : surface.distance_and_closest_point(x);
          last = q.closest_point;
        } else
          q.distance = surface.distance(x);
        if (!(std::abs(q.distance) < reach)) return std::abs(q.distance);
        const auto slot = static_cast<std::size_t>((c.i - origin.i) +
                                                   kBlock * ((c.j - origin.j) + kBlock * (c.k - origin.k)));
        psi[slot] = q.distance;
        closest[slot] = q.closest_point.value_or(x);
        entry.mask[slot / 64] |= std::uint64_t{1} << (slot % 64);
        return 0.0;
      });
      if (!near) continue;
      ++scanned[r];
      if (std::all_of(entry.mask.begin(), entry.mask.end(), [](std::uint64_t m) { return m == 0; })) continue;
      entry.first = static_cast<std::uint32_t>(row.psi.size());
      for (std::size_t slot = 0; slot < kSlots; ++slot) {
        if (std::isnan(psi[slot])) continue;
        row.psi.push_back(psi[slot]);
        if (exact_) row.closest.push_back(closest[slot]);
      }
      block_entry_[static_cast<std::size_t>(bi) + static_cast<std::size_t>(blocks_per_axis_[0]) * r] =
          static_cast<std::int32_t>(row.blocks.size());
      row.blocks.push_back(entry);
    }
    row.blocks.shrink_to_fit();
    row.psi.shrink_to_fit();
    row.closest.shrink_to_fit();
  });
  for (std::int64_t s : scanned) blocks_scanned_ += s;
}

bool NearField::locate(const Coord& c, const Row*& row, std::size_t& point) const {
  if (!grid_.contains(c)) return false;
  const int bi = c.i / kBlock, bj = c.j / kBlock, bk = c.k / kBlock;
  const std::int32_t e =
      block_entry_[static_cast<std::size_t>(bi) +
                   static_cast<std::size_t>(blocks_per_axis_[0]) *
                       (static_cast<std::size_t>(bj) +
                        static_cast<std::size_t>(blocks_per_axis_[1]) * static_cast<std::size_t>(bk))];
  if (e < 0) return false;
  row = &rows_[static_cast<std::size_t>(bj) +
               static_cast<std::size_t>(blocks_per_axis_[1]) * static_cast<std::size_t>(bk)];
  const BlockEntry& block = row->blocks[static_cast<std::size_t>(e)];
  const auto slot = static_cast<std::size_t>(
      (c.i - block.origin.i) + kBlock * ((c.j - block.origin.j) + kBlock * (c.k - block.origin.k)));
  const std::uint64_t word = block.mask[slot / 64];
  if (!((word >> (slot % 64)) & 1)) return false;
  // Rank of the slot among the block's points: the set bits below it.
  std::size_t rank = static_cast<std::size_t>(std::popcount(word & ((std::uint64_t{1} << (slot % 64)) - 1)));
  for (std::size_t w = 0; w < slot / 64; ++w) rank += static_cast<std::size_t>(std::popcount(block.mask[w]));
  point = block.first + rank;
  return true;
}

double NearField::psi(const Coord& c) const {
  const Row* row = nullptr;
  std::size_t point = 0;
  return locate(c, row, point) ? row->psi[point] : std::numeric_limits<double>::quiet_NaN();
}

Vec3 NearField::closest_point(const Coord& c) const {
  const Row* row = nullptr;
  std::size_t point = 0;
  if (!exact_ || !locate(c, row, point)) return Vec3::Constant(std::numeric_limits<double>::quiet_NaN());
  return row->closest[point];
}

}  // namespace poreshell
