#pragma once
// Trilinear interpolation on the grid's lattice: the cell a point lies in, the corner weights and the
// interpolation along rows. One rule for the band's stencils, the shell's sampling of phi, the
// multigrid's transfers and the sampled level set.

#include <cmath>

#include "core/types.hpp"

namespace poreshell {

// The cell of a point q given in index space (Grid::to_index_space): its lowest corner and q's
// position in it, per axis in [0, 1).
struct LatticeCell {
  Coord base;
  Vec3 t;
};
inline LatticeCell lattice_cell(const Vec3& q) {
  const Coord base{static_cast<int>(std::floor(q.x())), static_cast<int>(std::floor(q.y())),
                   static_cast<int>(std::floor(q.z()))};
  return {base, q - Vec3(base.i, base.j, base.k)};
}

// The weight of corner c = di + 2 dj + 4 dk of the cell at position t in it. The eight sum to 1 and
// reproduce linear functions exactly (up to round-off).
inline double trilinear_weight(const Vec3& t, int c) {
  return ((c & 1) ? t.x() : 1 - t.x()) * ((c & 2) ? t.y() : 1 - t.y()) * ((c & 4) ? t.z() : 1 - t.z());
}

// Trilinear interpolation from the cell's four rows along x: along_x(r) interpolates the row of corners
// (0, dj, dk), r = dj + 2 dk, at tx; then y, then z. Fewer operations than eight weights, for the
// solvers' ghost refreshes and transfers.
template <class T, class AlongX>
T trilinear_from_rows(AlongX&& along_x, T ty, T tz) {
  const T low = along_x(0) + ty * (along_x(1) - along_x(0));
  const T high = along_x(2) + ty * (along_x(3) - along_x(2));
  return low + tz * (high - low);
}

}  // namespace poreshell
