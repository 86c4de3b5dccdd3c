#pragma once
// Edge collapses that move the vertex they keep to where the two vertices' error quadrics are least,
// each measured against the original surface directly (placed_collapse.cpp).

#include <cstdint>
#include <vector>

#include "reduce/edge_collapse.hpp"

namespace poreshell {

// As collapse_edges(), with CollapsedMesh::positions set: where each kept vertex ended.
CollapsedMesh collapse_edges_placed(const TriangleMesh& mesh, const std::vector<std::int32_t>& opposite,
                                    const OriginalSurface& original, std::int64_t max_triangles,
                                    double tolerance, CollapseCounts& counts, const StageProgress& progress);

}  // namespace poreshell
