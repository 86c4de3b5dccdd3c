#pragma once
// Where a wall on an open surface ends (issue 19, item 3): at the surface's open boundary, with a flat
// face across the wall, perpendicular to the surface there. The unsigned distance alone makes a
// rounded cap past each boundary edge (half the wall, plus the offset) that wraps around the edge, and
// there an offset wall's side test has no jump to go by. The shell intersects its solid with the
// half-space behind the trim line instead: F = max(F, s), s the signed distance beyond the boundary
// along its outward tangent (in the plane of the boundary triangle, perpendicular to its boundary
// edge).

#include <optional>
#include <vector>

#include "core/cell_hash.hpp"
#include "core/types.hpp"
#include "geometry/mesh.hpp"

namespace poreshell {

class TrimLine {
 public:
  // The open boundary of `mesh` (edges with one triangle; zero-area triangles' edges are left out, they
  // have no plane), for queries up to `reach` from it.
  TrimLine(const TriangleMesh& mesh, double reach);

  bool empty() const { return edges_.empty(); }
  std::size_t edge_count() const { return edges_.size(); }

  // How far x lies beyond the trim line: (x - b) . tau, b the nearest boundary point and tau the outward
  // tangent there (the two ends' tangents interpolated along an edge, each the mean of the boundary
  // edges at that vertex, so that s is continuous around a curved boundary). Negative behind the line,
  // on the surface's side. Nothing where no boundary edge is within `reach` of x.
  std::optional<double> beyond(const Vec3& x) const;

 private:
  struct TrimEdge {
    Vec3 a, b;                  // the boundary edge
    Vec3 tangent_a, tangent_b;  // unit outward tangents at a and b
  };
  std::vector<TrimEdge> edges_;
  double reach_;
  CellHash cells_;  // edges within reach of a cell
};

}  // namespace poreshell
