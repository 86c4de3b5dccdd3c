#pragma once
// A lighter copy of a mesh for showing it (the HTML viewer), never for printing: vertices clustered on
// a grid, so that the triangle count falls under a budget in one pass over the mesh. OpenMesh's
// decimater keeps the surface within a bound but took 89 s to take the bunny's 2.0 M-triangle shell
// to 300 k; clustering takes well under a second and the difference is below what a screen shows.

#include <cstddef>
#include <cstdint>
#include <vector>

#include "geometry/mesh.hpp"

namespace poreshell {

// At most `max_triangles` triangles (the input itself when it has no more); orientation kept,
// triangles that collapse dropped. `shown_as`, if given, receives for each input vertex the reduced
// vertex it went into (the identity when nothing was reduced): per-vertex data follows the vertices
// through it.
TriangleMesh reduce_for_display(const TriangleMesh& mesh, std::size_t max_triangles,
                                std::vector<std::int32_t>* shown_as = nullptr);

}  // namespace poreshell
