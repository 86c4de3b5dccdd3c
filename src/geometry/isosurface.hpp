#pragma once
// Isosurface of a sparse scalar field on the grid. Values are given at a set of grid points;
// every other grid point holds `background`. The extracted surface bounds the region where the
// field is below `iso`, oriented outward (normals point towards larger values).

#include <span>

#include "core/grid.hpp"
#include "core/run_monitor.hpp"
#include "geometry/mesh.hpp"

namespace poreshell {

struct SparseField {
  const Grid* grid = nullptr;
  std::span<const Coord> points;
  std::span<const double> values;  // one per point
  double background = 1.0;
  // Optional, for a field that is the max of parts (an intersection of solids): values = the max of
  // the parts per point, points in ascending (k, j, i) order. A vertex then lies where the last of the
  // parts crosses along its edge (exact for parts linear along it), not where the interpolated max
  // does: the max has a crease, which interpolation rounds into a chamfer a cell wide (a pore's wall
  // flared by up to 0.1 mm where it met the shell's faces: circularity 0.956 -> 0.991 on a sphere).
  std::span<const std::span<const double>> parts = {};
  // With parts: vertices on their creases too (tet_creases.hpp), at most kMaxTetParts parts. Without, the
  // triangles cut across a crease as a chamfer up to half a cell deep. A crease point takes each part as
  // affine in a tetrahedron, also where another part is outside: each part must go on smoothly there (the
  // shell's slab past its trim line, shell.cpp).
  bool sharp_creases = true;
};

// Requires background > iso (the solid is bounded). The result is closed and 2-manifold.
TriangleMesh extract_isosurface(const SparseField& field, double iso, const StageProgress& progress = {});

// The Euler characteristic of extract_isosurface(field, iso) without making it: the solid {value <
// iso} retracts onto the simplices of the cubes' Kuhn triangulation whose corners are all inside, and a
// closed surface bounding a solid has twice the solid's characteristic. One pass over the inside points
// (vertices - edges + triangles - tetrahedra that start at each), no mesh.
std::int64_t isosurface_euler_characteristic(const SparseField& field, double iso,
                                             const StageProgress& progress = {});

}  // namespace poreshell
