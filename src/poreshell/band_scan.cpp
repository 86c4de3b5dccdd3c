#include "poreshell/band_scan.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <limits>

namespace poreshell {

namespace {

template <class Block>
void sort_slots(Block& block) {
  std::vector<std::size_t> order(block.slots.size());
  for (std::size_t n = 0; n < order.size(); ++n) order[n] = n;
  std::sort(order.begin(), order.end(),
            [&](std::size_t a, std::size_t b) { return block.slots[a] < block.slots[b]; });
  std::vector<std::uint16_t> slots(order.size());
  std::vector<Vec3> closest(order.size());
  for (std::size_t n = 0; n < order.size(); ++n) {
    slots[n] = block.slots[order[n]];
    closest[n] = block.closest[order[n]];
  }
  block.slots = std::move(slots);
  block.closest = std::move(closest);
}

}  // namespace

NearField::NearField(const Surface& surface, const Grid& grid, double reach) : grid_(grid) {
  const auto& d = grid.dims();
  for (int a = 0; a < 3; ++a) blocks_per_axis_[static_cast<std::size_t>(a)] = (d[a] + kBlock - 1) / kBlock;
  const std::int64_t count =
      std::int64_t{blocks_per_axis_[0]} * blocks_per_axis_[1] * std::int64_t{blocks_per_axis_[2]};
  blocks_.resize(static_cast<std::size_t>(count));
  const double h = grid.h();
  const double half_diagonal = 0.5 * std::sqrt(3.0) * (kBlock - 1) * h;
  const bool exact = surface.closest_point_is_exact();
  std::vector<char> scanned(blocks_.size(), 0);
  tbb::parallel_for(std::size_t{0}, blocks_.size(), [&](std::size_t b) {
    const auto bi = static_cast<std::int64_t>(b);
    const Coord origin{
        static_cast<int>(bi % blocks_per_axis_[0]) * kBlock,
        static_cast<int>((bi / blocks_per_axis_[0]) % blocks_per_axis_[1]) * kBlock,
        static_cast<int>(bi / (std::int64_t{blocks_per_axis_[0]} * blocks_per_axis_[1])) * kBlock};
    // psi is 1-Lipschitz: one query at the centre rules out the whole block.
    const Vec3 center = grid.position(origin) + Vec3::Constant(0.5 * (kBlock - 1) * h);
    if (std::abs(surface.distance(center)) > half_diagonal + reach) return;
    scanned[b] = 1;
    auto block = std::make_unique<Block>();
    block->origin = origin;
    block->psi.fill(std::numeric_limits<double>::quiet_NaN());
    bool any = false;
    // Sub-blocks of half the side, each ruled out by its own centre where it can: a block that the
    // surface only grazes is mostly beyond reach.
    constexpr int kHalf = kBlock / 2;
    const double half_sub_diagonal = 0.5 * std::sqrt(3.0) * (kHalf - 1) * h;
    for (int sub = 0; sub < 8; ++sub) {
      const Coord so{origin.i + (sub & 1) * kHalf, origin.j + ((sub >> 1) & 1) * kHalf,
                     origin.k + (sub >> 2) * kHalf};
      if (so.i >= d[0] || so.j >= d[1] || so.k >= d[2]) continue;
      const Vec3 sub_center = grid.position(so) + Vec3::Constant(0.5 * (kHalf - 1) * h);
      if (std::abs(surface.distance(sub_center)) > half_sub_diagonal + reach) continue;
      for (int k = so.k; k < std::min(so.k + kHalf, d[2]); ++k)
        for (int j = so.j; j < std::min(so.j + kHalf, d[1]); ++j)
          for (int i = so.i; i < std::min(so.i + kHalf, d[0]); ++i) {
            const Vec3 x = grid.position({i, j, k});
            SurfaceQuery q;
            if (exact)
              q = surface.distance_and_closest_point(x);
            else
              q.distance = surface.distance(x);
            const double far = std::abs(q.distance) - reach;
            if (!(far < 0.0)) {  // and the next points of the row that are as surely beyond reach
              if (std::isfinite(far)) i += static_cast<int>(std::floor(far / h));
              continue;
            }
            const int slot = (i - origin.i) + kBlock * ((j - origin.j) + kBlock * (k - origin.k));
            block->psi[static_cast<std::size_t>(slot)] = q.distance;
            any = true;
            if (q.closest_point) {
              block->slots.push_back(static_cast<std::uint16_t>(slot));
              block->closest.push_back(*q.closest_point);
            }
          }
    }
    // Slots were visited sub-block by sub-block: put them in order for the lookup.
    sort_slots(*block);
    if (any) blocks_[b] = std::move(block);
  });
  for (char s : scanned) blocks_scanned_ += s;
}

const NearField::Block* NearField::block_of(const Coord& c, int& slot) const {
  if (!grid_.contains(c)) return nullptr;
  const int bi = c.i / kBlock, bj = c.j / kBlock, bk = c.k / kBlock;
  slot = (c.i - bi * kBlock) + kBlock * ((c.j - bj * kBlock) + kBlock * (c.k - bk * kBlock));
  const std::size_t b = static_cast<std::size_t>(bi) +
                        static_cast<std::size_t>(blocks_per_axis_[0]) *
                            (static_cast<std::size_t>(bj) +
                             static_cast<std::size_t>(blocks_per_axis_[1]) * static_cast<std::size_t>(bk));
  return blocks_[b].get();
}

double NearField::psi(const Coord& c) const {
  int slot = 0;
  const Block* block = block_of(c, slot);
  return block != nullptr ? block->psi[static_cast<std::size_t>(slot)]
                          : std::numeric_limits<double>::quiet_NaN();
}

const Vec3* NearField::closest_point(const Coord& c) const {
  int slot = 0;
  const Block* block = block_of(c, slot);
  if (block == nullptr) return nullptr;
  const auto it =
      std::lower_bound(block->slots.begin(), block->slots.end(), static_cast<std::uint16_t>(slot));
  if (it == block->slots.end() || *it != slot) return nullptr;
  return &block->closest[static_cast<std::size_t>(it - block->slots.begin())];
}

}  // namespace poreshell
