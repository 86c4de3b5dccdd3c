#pragma once
// The clean-up every imported mesh gets, from a file or from memory: exact welding, unused vertices
// removed, degenerate and repeated triangles dropped.

#include <cstdint>

#include "geometry/mesh.hpp"

namespace poreshell {

struct MeshInputStats {
  std::int64_t vertices = 0;            // after welding exact duplicates and removing unused ones
  std::int64_t triangles = 0;           // after dropping degenerate ones
  std::int64_t dropped_degenerate = 0;  // repeated vertex or zero area
  std::int64_t boundary_edges = 0;      // edges with one triangle (holes, open borders)
  std::int64_t dropped_duplicate = 0;   // a triangle on the same three vertices as an earlier one
};

// Welds vertices with identical coordinates, removes unused vertices and drops degenerate triangles and
// repeats of a triangle (the same three vertices, either orientation).
// Throws InputError if a used vertex is NaN/inf or nothing is left.
MeshInputStats clean_triangle_mesh(TriangleMesh& mesh);

}  // namespace poreshell
