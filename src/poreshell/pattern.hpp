#pragma once
// Pattern statistics on the band: the spots {phi > level} as connected components of band voxels
// (6-connectivity through the band's neighbour table).

#include <cstdint>
#include <span>
#include <vector>

#include "poreshell/band.hpp"

namespace poreshell {

struct SpotStats {
  std::int64_t count = 0;
  std::vector<std::int64_t> sizes;  // voxels per spot, in order of first voxel
  double mean_size = 0.0;
  double size_cv = 0.0;        // standard deviation / mean of the sizes
  double area_fraction = 0.0;  // share of band voxels inside spots
  // Distance from each spot's centroid to the nearest other centroid (grid units): mean and CV.
  double spacing_mean = 0.0;
  double spacing_cv = 0.0;
};

// Component label per band voxel (-1 outside every spot).
std::vector<std::int32_t> label_spots(const NarrowBand& band, std::span<const double> phi, double level);

SpotStats spot_statistics(const NarrowBand& band, std::span<const double> phi, double level);

}  // namespace poreshell
