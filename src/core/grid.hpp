#pragma once
// The uniform grid of the paper (section 2): x_ijk = origin + h * (i, j, k), 0 <= i < Nx etc.
// The paper counts from 1; we count from 0. This is the single place that knows the convention.

#include <algorithm>
#include <array>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/types.hpp"

namespace poreshell {

class Grid {
 public:
  Grid(const Vec3& origin, double h, std::array<int, 3> dims);

  // The grid that covers [lo, hi] with `points_longest` points along the longest side
  // (the paper's N; h = longest side / (N - 1)).
  static Grid fitted(const Box& box, int points_longest);

  const Vec3& origin() const { return origin_; }
  double h() const { return h_; }
  const std::array<int, 3>& dims() const { return dims_; }
  std::int64_t cell_count() const { return std::int64_t{dims_[0]} * dims_[1] * dims_[2]; }

  Vec3 position(const Coord& c) const { return origin_ + h_ * Vec3(c.i, c.j, c.k); }
  // Position in grid units: (p - origin) / h.
  Vec3 to_index_space(const Vec3& p) const { return (p - origin_) / h_; }

  bool contains(const Coord& c) const {
    return c.i >= 0 && c.j >= 0 && c.k >= 0 && c.i < dims_[0] && c.j < dims_[1] && c.k < dims_[2];
  }
  // Linear key with i fastest: key = i + Nx * (j + Ny * k). Used for sorting and lookup only;
  // nothing allocates Nx*Ny*Nz storage.
  std::int64_t key(const Coord& c) const {
    return c.i + std::int64_t{dims_[0]} * (c.j + std::int64_t{dims_[1]} * c.k);
  }
  Coord coord(std::int64_t key) const;

 private:
  Vec3 origin_;
  double h_;
  std::array<int, 3> dims_;
};

// The 6 face neighbours' offsets, -x, +x, -y, +y, -z, +z.
inline constexpr std::array<Coord, 6> kFaceOffsets{
    {{-1, 0, 0}, {1, 0, 0}, {0, -1, 0}, {0, 1, 0}, {0, 0, -1}, {0, 0, 1}}};

inline Coord shifted(const Coord& c, const Coord& offset) {
  return {c.i + offset.i, c.j + offset.j, c.k + offset.k};
}

// The position of `key` in ascending `keys`, or -1: sparse sets of voxels are sorted key lists.
inline std::int64_t find_key(const std::vector<std::int64_t>& keys, std::int64_t key) {
  const auto it = std::lower_bound(keys.begin(), keys.end(), key);
  return (it != keys.end() && *it == key) ? it - keys.begin() : -1;
}

}  // namespace poreshell
