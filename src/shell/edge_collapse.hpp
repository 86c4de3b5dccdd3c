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
#include "shell/collapse_bounds.hpp"
#include "shell/mesh_decimate.hpp"

namespace poreshell {

// The triangles of `mesh` left after collapsing edges until at most max_triangles remain or no
// collapse passes the rules, as indices into mesh.vertices, in their original order. `opposite` is
// opposite_corners(mesh); `original` is built over mesh and opposite. Deterministic. Adds the
// collapses made to `counts`.
std::vector<std::array<std::int32_t, 3>> collapse_edges(const TriangleMesh& mesh,
                                                        const std::vector<std::int32_t>& opposite,
                                                        const OriginalSurface& original,
                                                        std::int64_t max_triangles, double tolerance,
                                                        DistanceRule rule, CollapseCounts& counts,
                                                        const StageProgress& progress);

}  // namespace poreshell
