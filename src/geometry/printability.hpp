#pragma once
// What a slicer needs of a mesh: closed, manifold, consistently oriented, no degenerate triangles,
// positive volume. One check for every mesh the library hands out (meshed and reduced alike).

#include <string>

#include "geometry/mesh.hpp"

namespace poreshell {

// The failed checks, comma-separated ("3 boundary edges, volume not positive"); empty when printable.
std::string printability_failures(const MeshTopology& topology);

// Throws Error(internal) naming every failed check of the solid at pore level `iso`.
void check_printable(const MeshTopology& topology, double iso);

}  // namespace poreshell
