#pragma once
// Where to measure the printed wall, and which side of the surface is outside: the two things the
// shell needs of the input beyond its distance.

#include <optional>
#include <span>
#include <vector>

#include "band/band.hpp"
#include "geometry/winding_number.hpp"
#include "input/placement.hpp"
#include "measure/hole_table.hpp"
#include "measure/wall_measure.hpp"
#include "pattern/pattern.hpp"
#include "shell/shell.hpp"

namespace poreshell {

// Which side of the surface a point lies on, where the wall's offset needs it: a mesh input's winding
// number (shapes have a signed distance: no function needed). Not movable: `side` refers to `winding`.
struct SideTest {
  SideTest() = default;
  SideTest(const SideTest&) = delete;
  SideTest& operator=(const SideTest&) = delete;
  std::optional<WindingNumber> winding;
  SideFunction side;
};

// Sets `test` up for `offset`; throws OptionError where the input has no inside (point clouds).
void make_side_test(WallOffset offset, const PlacedSurface& placed, double h, SideTest& test);

// Probes across the shell's wall (mm) at up to 256 band voxels well inside the solid (phi nearer its
// minimum than the pore level, so away from pore rims, where a probe would graze the rim's wall),
// spread by band order.
std::vector<WallProbe> wall_probes(const PlacedSurface& placed, const NarrowBand& band,
                                   std::span<const double> phi, double iso, double wall_mm, WallOffset offset,
                                   const SideFunction& side);

// The hole table of one output (mm): each band hole's centroid (mm) seeds a cut through the wall's
// middle (the surface itself for the narrow volume), reaching its band diameter and two of the solid's
// cells beyond. Normals point outward: a mesh's winding number, also where a centred wall did not need
// it.
HoleTable output_hole_table(const TriangleMesh& mesh_mm, const HoleStats& holes_mm,
                            const PlacedSurface& placed, double h, double wall_mm, double cell_mm,
                            WallOffset offset, const SideFunction& side);

// Of the band's spots that open no closed hole in the mesh (HoleTable::uncut), those the open boundary
// cuts (notches): their centre within their radius and a wall of it. The rest did not cut through the
// wall (issue 51: the paper route's spot and pore counts differed without a word).
std::int64_t spots_at_open_edge(const HoleTable& table, const HoleStats& holes_mm,
                                const PlacedSurface& placed, double wall_mm);

}  // namespace poreshell
