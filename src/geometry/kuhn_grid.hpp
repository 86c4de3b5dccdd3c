#pragma once
// What the isosurface's polygonizer walks: the Kuhn (Freudenthal) triangulation of a cube, with the
// surface patch of each sign pattern of a tetrahedron, and the sparse field on the grid padded by one
// layer, read cube by cube in ascending key order by forward cursors (no search per cube).

#include <algorithm>
#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "geometry/isosurface.hpp"

namespace poreshell::kuhn {

// Vertex names: point key * kNames + what the vertex lies on, from that point (its lowest corner):
// 1-7 a grid edge (its direction bits); kFaceNames a Kuhn triangle's crease point; kInsideNames a
// crease meeting point inside one of the cube's tetrahedra (tet_creases.hpp).
constexpr std::int64_t kNames = 256, kFaceNames = 8, kInsideNames = 200;

// Cube corners are 3-bit masks (bit 0: +x, bit 1: +y, bit 2: +z).
using Tet = std::array<int, 4>;

// One surface patch per tetrahedron sign pattern: 3 or 4 tet edges (pairs of tet vertices) in
// counter-clockwise order seen from outside (from the larger values).
struct Patch {
  int size = 0;
  std::array<std::array<int, 2>, 4> edges{};
};

struct Tables {
  std::array<Tet, 6> tets{};
  std::array<Patch, 16> patches{};  // by inside mask over the 4 tet vertices
};

const Tables& tables();

// The grid padded by one layer on each side, so the cells around points on the grid boundary
// (whose far corners hold the background) have valid keys.
struct PaddedGrid {
  std::int64_t nx, ny, nz;
  std::int64_t key(const Coord& c) const { return (c.i + 1) + nx * ((c.j + 1) + ny * (c.k + 1)); }
  std::int64_t offset(int corner) const {
    return (corner & 1) + nx * ((corner >> 1) & 1) + nx * ny * (corner >> 2);
  }
  // Grid-index coordinates of a padded key (may be -1 or N).
  Vec3 index(std::int64_t key) const {
    return Vec3(static_cast<double>(key % nx - 1), static_cast<double>((key / nx) % ny - 1),
                static_cast<double>(key / (nx * ny) - 1));
  }
};

// The field as sorted (padded key, value) arrays; missing points hold the background.
struct FieldLookup {
  std::vector<std::int64_t> keys;
  std::vector<double> values;
  double background = 1.0;
  std::span<const std::span<const double>> parts;  // SparseField's, in key order (empty: none)

  std::optional<std::size_t> position(std::int64_t key) const {
    const auto it = std::lower_bound(keys.begin(), keys.end(), key);
    if (it == keys.end() || *it != key) return std::nullopt;
    return static_cast<std::size_t>(it - keys.begin());
  }
  double at(std::int64_t key) const {
    const std::optional<std::size_t> p = position(key);
    return p ? values[*p] : background;
  }
};

// Checks the field (points in the grid, no NaN, each point once) and sorts it by key.
FieldLookup sorted_field(const SparseField& field, const PaddedGrid& grid);
// The padded grid, or why the field cannot be extracted at iso.
PaddedGrid checked_grid(const SparseField& field, double iso);

// The 8 corner values of cubes visited in ascending key order, read by four forward cursors (one per
// row of the cube along x) instead of a binary search per row and cube: consecutive cubes share rows,
// so a cursor moves a few entries, and over a chunk each walks its key range once. The searches were
// half the extraction at millions of samples.
class CornerReader {
 public:
  CornerReader(const FieldLookup& field, const PaddedGrid& grid, std::int64_t first_cell)
      : field_(field), grid_(grid) {
    for (int r = 0; r < 4; ++r)
      at_[static_cast<std::size_t>(r)] = static_cast<std::size_t>(
          std::lower_bound(field.keys.begin(), field.keys.end(), first_cell + grid.offset(r << 1)) -
          field.keys.begin());
  }

  // Corner c = bit 0 (+x), bit 1 (+y), bit 2 (+z); cell must not be below the previous one. `positions`
  // receives each corner's place in the field (-1: not sampled).
  std::array<double, 8> at(std::int64_t cell, std::array<std::int64_t, 8>* positions = nullptr) {
    std::array<double, 8> v;
    const std::size_t n = field_.keys.size();
    for (int r = 0; r < 4; ++r) {
      const std::int64_t key = cell + grid_.offset(r << 1);
      std::size_t& i = at_[static_cast<std::size_t>(r)];
      while (i < n && field_.keys[i] < key) ++i;
      for (int x = 0; x < 2; ++x) {
        const std::size_t j = i + static_cast<std::size_t>(x > 0 && i < n && field_.keys[i] == key);
        const bool sampled = j < n && field_.keys[j] == key + x;
        v[static_cast<std::size_t>((r << 1) | x)] = sampled ? field_.values[j] : field_.background;
        if (positions)
          (*positions)[static_cast<std::size_t>((r << 1) | x)] = sampled ? static_cast<std::int64_t>(j) : -1;
      }
    }
    return v;
  }

 private:
  const FieldLookup& field_;
  const PaddedGrid& grid_;
  std::array<std::size_t, 4> at_{};
};

// The vertex index (position among all sorted edge names) of a cube's edges, for cubes visited in
// ascending key order, by four forward cursors like CornerReader's: an edge's lower end is a corner of
// its cube, so its name lies a few entries past the cursor of that corner's row. A binary search per
// triangle corner over the names was a fifth of the extraction at 30 M triangles.
class NameReader {
 public:
  NameReader(const std::vector<std::int64_t>& names, const PaddedGrid& grid, std::int64_t first_cell)
      : names_(names), grid_(grid) {
    for (int r = 0; r < 4; ++r)
      at_[static_cast<std::size_t>(r)] = static_cast<std::size_t>(
          std::lower_bound(names.begin(), names.end(), kNames * (first_cell + grid.offset(r << 1))) -
          names.begin());
  }

  // cell must not be below the previous one.
  void move_to(std::int64_t cell) {
    for (int r = 0; r < 4; ++r) {
      const std::int64_t first_name = kNames * (cell + grid_.offset(r << 1));
      std::size_t& i = at_[static_cast<std::size_t>(r)];
      while (i < names_.size() && names_[i] < first_name) ++i;
    }
  }
  // Index of `name`, an edge of `cell` (the cell of the last move_to).
  std::size_t index(std::int64_t cell, std::int64_t name) const {
    const std::int64_t d = name / kNames - cell;  // the lowest corner's offset
    const std::size_t row =
        (d >= grid_.offset(4) ? 2 : 0) + ((d % grid_.offset(4)) >= grid_.offset(2) ? 1 : 0);
    std::size_t i = at_[row];
    while (names_[i] < name) ++i;
    return i;
  }

 private:
  const std::vector<std::int64_t>& names_;
  const PaddedGrid& grid_;
  std::array<std::size_t, 4> at_{};
};

}  // namespace poreshell::kuhn
