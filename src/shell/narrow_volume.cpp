#include "shell/narrow_volume.hpp"

#include <cmath>
#include <vector>

#include "geometry/isosurface.hpp"

namespace poreshell {
namespace {

// The band's values and its ghosts (outside: 1) as a field on the band's grid.
template <class Use>
auto with_narrow_volume_field(const NarrowBand& band, std::span<const double> phi, const Use& use) {
  std::vector<Coord> points(band.voxels().begin(), band.voxels().end());
  points.insert(points.end(), band.ghosts().begin(), band.ghosts().end());
  std::vector<double> values(phi.begin(), phi.end());
  values.resize(points.size(), 1.0);
  return use(SparseField{&band.grid(), points, values, 1.0});
}

}  // namespace

TriangleMesh narrow_volume_mesh(const NarrowBand& band, std::span<const double> phi, double iso) {
  return with_narrow_volume_field(band, phi,
                                  [&](const SparseField& f) { return extract_isosurface(f, iso); });
}

TriangleMesh surface_slab_mesh(const NarrowBand& band) {
  std::vector<double> slab(band.size());
  const double h = band.grid().h();
  for (std::size_t v = 0; v < slab.size(); ++v) slab[v] = std::abs(band.distance()[v]) - h;
  return narrow_volume_mesh(band, slab, 0.0);
}

std::int64_t narrow_volume_euler(const NarrowBand& band, std::span<const double> phi, double iso) {
  return with_narrow_volume_field(
      band, phi, [&](const SparseField& f) { return isosurface_euler_characteristic(f, iso); });
}

}  // namespace poreshell
