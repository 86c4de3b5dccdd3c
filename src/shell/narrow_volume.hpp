#pragma once
// The narrow volume of Fig. 3(b): phi on the band, 1 on the ghosts and everywhere else; the solid is
// {phi < iso}.

#include <cstdint>
#include <span>

#include "band/band.hpp"
#include "geometry/mesh.hpp"

namespace poreshell {

// Its isosurface.
TriangleMesh narrow_volume_mesh(const NarrowBand& band, std::span<const double> phi, double iso);
// The surface itself at the band's resolution, for showing (a preview): the slab {|psi| < h} around it,
// closed and manifold (every grid cube the surface crosses has a corner within sqrt(3)/2 h of it).
TriangleMesh surface_slab_mesh(const NarrowBand& band);
// Its Euler characteristic, without making it.
std::int64_t narrow_volume_euler(const NarrowBand& band, std::span<const double> phi, double iso);

}  // namespace poreshell
