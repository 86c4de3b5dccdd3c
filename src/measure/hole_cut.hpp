#pragma once
// Each seed's hole found on the mesh's triangles: the smallest closed loop around the seed where the
// cut through the wall's middle crosses them, measured (hole_table.hpp says how). measure_holes makes
// the table from these.

#include <optional>
#include <span>
#include <vector>

#include "measure/hole_table.hpp"

namespace poreshell {

// Per seed, its hole, or nothing where no loop around it bounds an opening (and for seeds of reach 0).
// Deterministic, whatever the thread count.
std::vector<std::optional<HoleRecord>> cut_holes(const TriangleMesh& mesh, std::span<const HoleSeed> seeds,
                                                 const MidWall* mid_wall);

}  // namespace poreshell
