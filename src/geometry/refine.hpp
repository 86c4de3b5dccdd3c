#pragma once
// A mesh's triangles split until no edge is longer than a length, for painting a field on the mesh at
// that resolution (a preview's pattern on the input surface): a CAD export's long thin triangles would
// otherwise show a hole as a smear across a few vertices.

#include <cstddef>

#include "geometry/mesh.hpp"

namespace poreshell {

// Splits every edge longer than `longest` at its midpoint, the same way in both of its triangles (no
// T-junctions: the result is conforming wherever the input is), each triangle into 2, 3 or 4 by how
// many of its edges split, and again until none is too long or the next round would pass
// `max_triangles`. Keeps orientation, boundaries and the vertices' order (new ones are appended).
TriangleMesh split_long_edges(TriangleMesh mesh, double longest, std::size_t max_triangles);

// A preview's mesh input painted at the band's resolution h: edges split down to sqrt(2) h (a grid
// face's diagonal, the longest edge marching cubes make on that grid), into at most 2 M triangles or
// the input's count (about 2.5 times the bunny's slab at 8 mm holes).
TriangleMesh preview_surface_mesh(const TriangleMesh& mesh, double h);

}  // namespace poreshell
