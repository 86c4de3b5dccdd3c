#pragma once
// The edge collapses of the triangle reduction (mesh_decimate.hpp), on flat arrays: halfedge
// collapses onto existing vertices, least error quadric first, each made only where
// - the mesh stays 2-manifold (the link condition) and keeps its genus and components;
// - no new triangle has an angle below 10 degrees, unless one of those it replaces had one at least
//   as small: collapsing next to a sliver of the input is how it goes away, so slivers must not
//   freeze their neighbourhood;
// - no new triangle faces away from the original surface at its corners;
// - the new triangles are within the tolerance of the original surface, both ways: everywhere, by a
//   bound that follows from the old and new triangles and the old ones' bounds (on smooth parts of
//   the surface); else at the points decimate_mesh() measures: the centroids of the new triangles
//   and the midpoints of the new edges are within the tolerance of the original surface, and the
//   original vertices removed so far within the tolerance of the triangles around them.

#include <array>
#include <cstdint>
#include <vector>

#include "geometry/mesh.hpp"
#include "reduce/collapse_bounds.hpp"
#include "reduce/mesh_decimate.hpp"

namespace poreshell {

// What the collapses leave: the triangles, as indices into the original's vertices, in their original
// order; and for each original vertex the triangle (an index into `triangles`) it was last distributed
// over, -1 for the vertices the triangles keep. A removed vertex's distance to that triangle bounds its
// distance to the reduced surface.
struct CollapsedMesh {
  std::vector<std::array<std::int32_t, 3>> triangles;
  std::vector<std::int32_t> carrier;
  // Where each vertex is, for collapses that move the vertices they keep; empty where none moved.
  std::vector<Vec3> positions;
};

// Collapses edges of `mesh` until at most max_triangles remain or no collapse passes the rules.
// `opposite` is opposite_corners(mesh); `original` is built over mesh and opposite. Deterministic. Adds
// the collapses made to `counts`.
CollapsedMesh collapse_edges(const TriangleMesh& mesh, const std::vector<std::int32_t>& opposite,
                             const OriginalSurface& original, std::int64_t max_triangles, double tolerance,
                             DistanceRule rule, CollapseCounts& counts, const StageProgress& progress);

}  // namespace poreshell
