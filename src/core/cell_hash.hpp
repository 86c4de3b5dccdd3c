#pragma once
// A spatial hash of cubic cells: ids (seeds, rays, segments, edges) registered in the cells of size
// `cell` that they reach, looked up by cell. Keys keep 21 bits of each cell index, so cells 2^21 apart
// share a key: a lookup can then list more ids than are near, never fewer, and every user filters by
// distance. Entries are one sorted array rather than a map of vectors: a cell lists its ids in ascending
// order, the order in which its users registered them, so results that break ties by order are kept.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "core/types.hpp"

namespace poreshell {

// The key of cell (i, j, k): 21 bits of each index (wrapping, see above).
inline std::int64_t cell_key(std::int64_t i, std::int64_t j, std::int64_t k) {
  return ((i & 0x1FFFFF) << 42) | ((j & 0x1FFFFF) << 21) | (k & 0x1FFFFF);
}

class CellHash {
 public:
  explicit CellHash(double cell) : cell_(cell) {}

  double cell() const { return cell_; }
  std::int64_t cell_of(double x) const { return static_cast<std::int64_t>(std::floor(x / cell_)); }

  // Registers `id` in cell (i, j, k); seal() before looking up.
  void add(std::int64_t i, std::int64_t j, std::int64_t k, std::uint32_t id) {
    entries_.push_back({cell_key(i, j, k), id});
  }
  // Registers `id` in every cell the box [lo, hi] meets.
  void add_box(const Vec3& lo, const Vec3& hi, std::uint32_t id) {
    for (std::int64_t i = cell_of(lo.x()); i <= cell_of(hi.x()); ++i)
      for (std::int64_t j = cell_of(lo.y()); j <= cell_of(hi.y()); ++j)
        for (std::int64_t k = cell_of(lo.z()); k <= cell_of(hi.z()); ++k) add(i, j, k, id);
  }
  // Sorts the entries and drops repeats (an id registered twice in one cell is listed once).
  void seal() {
    std::sort(entries_.begin(), entries_.end());
    entries_.erase(std::unique(entries_.begin(), entries_.end()), entries_.end());
  }

  // Calls f(id) for the ids registered in cell (i, j, k), ascending.
  template <class F>
  void for_each_in(std::int64_t i, std::int64_t j, std::int64_t k, const F& f) const {
    const std::int64_t key = cell_key(i, j, k);
    auto it = std::lower_bound(entries_.begin(), entries_.end(), Entry{key, 0});
    for (; it != entries_.end() && it->cell == key; ++it) f(it->id);
  }
  // The same for the cell that holds p.
  template <class F>
  void for_each_at(const Vec3& p, const F& f) const {
    for_each_in(cell_of(p.x()), cell_of(p.y()), cell_of(p.z()), f);
  }

 private:
  struct Entry {
    std::int64_t cell;
    std::uint32_t id;
    bool operator<(const Entry& o) const { return cell != o.cell ? cell < o.cell : id < o.id; }
    bool operator==(const Entry& o) const { return cell == o.cell && id == o.id; }
  };
  double cell_;
  std::vector<Entry> entries_;
};

}  // namespace poreshell
