#include "poreshell/band_scan.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>

namespace poreshell {

NearField::NearField(const Surface& surface, const Grid& grid, double reach)
    : grid_(grid), exact_(surface.closest_point_is_exact()) {
  const auto& d = grid.dims();
  for (std::size_t a = 0; a < 3; ++a) blocks_per_axis_[a] = (d[a] + kBlock - 1) / kBlock;
  block_entry_.assign(static_cast<std::size_t>(blocks_per_axis_[0]) *
                          static_cast<std::size_t>(blocks_per_axis_[1]) *
                          static_cast<std::size_t>(blocks_per_axis_[2]),
                      -1);
  rows_.resize(static_cast<std::size_t>(blocks_per_axis_[1]) * static_cast<std::size_t>(blocks_per_axis_[2]));
  const double h = grid.h();
  constexpr int kHalf = kBlock / 2, kQuarter = kBlock / 4;
  const double half_diagonal = 0.5 * std::sqrt(3.0) * (kBlock - 1) * h;
  const double half_sub_diagonal = 0.5 * std::sqrt(3.0) * (kHalf - 1) * h;
  const double half_quad_diagonal = 0.5 * std::sqrt(3.0) * (kQuarter - 1) * h;
  std::vector<std::int64_t> scanned(rows_.size(), 0);
  tbb::parallel_for(std::size_t{0}, rows_.size(), [&](std::size_t r) {
    Row& row = rows_[r];
    const auto bj = static_cast<int>(r % static_cast<std::size_t>(blocks_per_axis_[1]));
    const auto bk = static_cast<int>(r / static_cast<std::size_t>(blocks_per_axis_[1]));
    std::array<double, kSlots> psi;
    std::array<Vec3, kSlots> closest;
    for (int bi = 0; bi < blocks_per_axis_[0]; ++bi) {
      const Coord origin{bi * kBlock, bj * kBlock, bk * kBlock};
      // psi is 1-Lipschitz: one query at a block's centre can rule out the whole block, and then
      // each of its eighths (a block that the surface only grazes is mostly beyond reach).
      const Vec3 center = grid.position(origin) + Vec3::Constant(0.5 * (kBlock - 1) * h);
      if (std::abs(surface.distance(center)) > half_diagonal + reach) continue;
      ++scanned[r];
      BlockEntry entry;
      entry.origin = origin;
      psi.fill(std::numeric_limits<double>::quiet_NaN());
      // The exact test at each point of [lo, lo + side)^3 within the grid.
      const auto scan_points = [&](const Coord& lo, int side) {
        for (int k = lo.k; k < std::min(lo.k + side, d[2]); ++k)
          for (int j = lo.j; j < std::min(lo.j + side, d[1]); ++j)
            for (int i = lo.i; i < std::min(lo.i + side, d[0]); ++i) {
              const Vec3 x = grid.position({i, j, k});
              SurfaceQuery q;
              if (exact_)
                q = surface.distance_and_closest_point(x);
              else
                q.distance = surface.distance(x);
              const double far = std::abs(q.distance) - reach;
              if (!(far < 0.0)) {  // and the next points of the row that are as surely beyond reach
                if (std::isfinite(far)) i += static_cast<int>(std::floor(far / h));
                continue;
              }
              const auto slot = static_cast<std::size_t>((i - origin.i) +
                                                         kBlock * ((j - origin.j) + kBlock * (k - origin.k)));
              psi[slot] = q.distance;
              closest[slot] = q.closest_point.value_or(x);
              entry.mask[slot / 64] |= std::uint64_t{1} << (slot % 64);
            }
      };
      // Eighths, and their eighths where the surface only grazes them; an eighth wholly within reach
      // is scanned at once (splitting it would only add queries).
      for (int sub = 0; sub < 8; ++sub) {
        const Coord so{origin.i + (sub & 1) * kHalf, origin.j + ((sub >> 1) & 1) * kHalf,
                       origin.k + (sub >> 2) * kHalf};
        if (so.i >= d[0] || so.j >= d[1] || so.k >= d[2]) continue;
        const Vec3 sub_center = grid.position(so) + Vec3::Constant(0.5 * (kHalf - 1) * h);
        const double sub_distance = std::abs(surface.distance(sub_center));
        if (sub_distance > half_sub_diagonal + reach) continue;
        if (sub_distance + half_sub_diagonal <= reach) {
          scan_points(so, kHalf);
          continue;
        }
        for (int quad = 0; quad < 8; ++quad) {
          const Coord qo{so.i + (quad & 1) * kQuarter, so.j + ((quad >> 1) & 1) * kQuarter,
                         so.k + (quad >> 2) * kQuarter};
          if (qo.i >= d[0] || qo.j >= d[1] || qo.k >= d[2]) continue;
          const Vec3 quad_center = grid.position(qo) + Vec3::Constant(0.5 * (kQuarter - 1) * h);
          if (std::abs(surface.distance(quad_center)) > half_quad_diagonal + reach) continue;
          scan_points(qo, kQuarter);
        }
      }
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
