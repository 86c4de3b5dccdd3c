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
// Its Euler characteristic, without making it.
std::int64_t narrow_volume_euler(const NarrowBand& band, std::span<const double> phi, double iso);

}  // namespace poreshell
