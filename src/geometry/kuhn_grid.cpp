#include "geometry/kuhn_grid.hpp"

#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <bit>
#include <cmath>
#include <stdexcept>
#include <string>

#include "core/error.hpp"
#include "geometry/tet_creases.hpp"

namespace poreshell::kuhn {
namespace {

int corner_det(const Tet& t) {
  auto v = [](int c, int a) { return (c >> a) & 1; };
  int m[3][3];
  for (int r = 0; r < 3; ++r)
    for (int a = 0; a < 3; ++a) m[r][a] = v(t[r + 1], a) - v(t[0], a);
  return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
         m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
         m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
}

Tables make_tables() {
  Tables tables;
  std::array<int, 3> axes{0, 1, 2};
  int n = 0;
  do {  // Kuhn tetrahedron: walk from corner 0 to corner 7 adding one axis at a time.
    const int a = 1 << axes[0], b = a | (1 << axes[1]);
    Tet t{0, a, b, 7};
    if (corner_det(t) < 0) std::swap(t[2], t[3]);  // positive orientation for the patch table
    tables.tets[n++] = t;
  } while (std::next_permutation(axes.begin(), axes.end()));

  // Even permutations of the tet vertices keep the orientation positive. For (p0, p1, p2, p3)
  // positive, the triangle (p0p1, p0p2, p0p3) faces away from p0 (derivation: its normal dotted
  // with p1 - p0 is the tet's determinant).
  std::array<int, 4> p{0, 1, 2, 3};
  std::vector<std::array<int, 4>> even;
  do {
    int inversions = 0;
    for (int i = 0; i < 4; ++i)
      for (int j = i + 1; j < 4; ++j) inversions += p[i] > p[j];
    if (inversions % 2 == 0) even.push_back(p);
  } while (std::next_permutation(p.begin(), p.end()));

  for (int mask = 1; mask < 15; ++mask) {
    Patch& patch = tables.patches[mask];
    const int inside = std::popcount(static_cast<unsigned>(mask));
    for (const auto& q : even) {
      const bool in0 = (mask >> q[0]) & 1, in1 = (mask >> q[1]) & 1;
      if (inside == 1 && in0) {  // faces away from the inside vertex q0
        patch = {3, {{{q[0], q[1]}, {q[0], q[2]}, {q[0], q[3]}}}};
        break;
      }
      if (inside == 3 && !in0) {  // faces towards the outside vertex q0
        patch = {3, {{{q[0], q[1]}, {q[0], q[3]}, {q[0], q[2]}}}};
        break;
      }
      if (inside == 2 && in0 && in1) {  // quad around the inside edge q0q1
        patch = {4, {{{q[0], q[2]}, {q[0], q[3]}, {q[1], q[3]}, {q[1], q[2]}}}};
        break;
      }
    }
  }
  return tables;
}

}  // namespace

const Tables& tables() {
  static const Tables t = make_tables();
  return t;
}

FieldLookup sorted_field(const SparseField& field, const PaddedGrid& grid) {
  const std::size_t n = field.points.size();
  for (std::size_t p = 0; p < n; ++p) {
    if (!field.grid->contains(field.points[p]))
      throw std::invalid_argument("isosurface: point outside the grid");
    if (std::isnan(field.values[p])) throw std::invalid_argument("isosurface: NaN field value");
  }
  FieldLookup lookup;
  lookup.background = field.background;
  lookup.keys.resize(n);
  lookup.values.resize(n);
  // Points given in key order (the shell's samples) are taken as they are: no sorted copy.
  const auto by_key = [&](const Coord& a, const Coord& b) { return grid.key(a) < grid.key(b); };
  const bool sorted = std::is_sorted(field.points.begin(), field.points.end(), by_key);
  if (!field.parts.empty()) {
    const bool sized =
        std::all_of(field.parts.begin(), field.parts.end(), [&](auto p) { return p.size() == n; });
    if (!sorted || !sized)
      throw std::invalid_argument("isosurface: parts need points in key order, one value each");
    if (field.parts.size() > kMaxTetParts) throw std::invalid_argument("isosurface: at most 3 parts");
    lookup.parts = field.parts;
  }
  if (sorted) {
    tbb::parallel_for(std::size_t{0}, n, [&](std::size_t p) {
      lookup.keys[p] = grid.key(field.points[p]);
      lookup.values[p] = field.values[p];
    });
  } else {
    std::vector<std::pair<std::int64_t, double>> entries(n);
    for (std::size_t p = 0; p < n; ++p) entries[p] = {grid.key(field.points[p]), field.values[p]};
    tbb::parallel_sort(entries.begin(), entries.end());
    for (std::size_t p = 0; p < n; ++p) {
      lookup.keys[p] = entries[p].first;
      lookup.values[p] = entries[p].second;
    }
  }
  if (std::adjacent_find(lookup.keys.begin(), lookup.keys.end()) != lookup.keys.end())
    throw std::invalid_argument("isosurface: the same grid point is given twice");
  return lookup;
}

PaddedGrid checked_grid(const SparseField& field, double iso) {
  if (field.grid == nullptr || field.points.size() != field.values.size())
    throw std::invalid_argument("isosurface: field needs a grid and one value per point");
  if (!(field.background > iso))
    throw InputError("the iso level must be below the background value " + std::to_string(field.background));
  const auto& dims = field.grid->dims();
  const PaddedGrid grid{dims[0] + 2, dims[1] + 2, dims[2] + 2};
  if (static_cast<double>(grid.nx) * static_cast<double>(grid.ny) * static_cast<double>(grid.nz) >
      0x1p54)  // names: key * kNames
    throw InputError("the grid is too large for isosurface extraction; lower the resolution");
  return grid;
}

}  // namespace poreshell::kuhn
