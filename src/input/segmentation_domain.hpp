#pragma once
// Where the segmentation PDE (eq. 3.3) is solved: the sparse band of lattice voxels near the points, its
// ghost layer, and which side of the points each of them lies on.

#include <array>
#include <cstdint>
#include <vector>

#include "core/grid.hpp"
#include "geometry/point_tree.hpp"

namespace poreshell {

// The sparse domain of eq. (3.3): lattice voxels with g < width, found by a breadth-first search from
// the voxels nearest the points (never a dense array), and its ghost layer: their 6-neighbours with
// g >= width. Both sorted by key, with g at each.
struct SegmentationDomain {
  std::vector<std::int64_t> band, ghost;
  std::vector<double> band_g;
};

SegmentationDomain find_segmentation_domain(const Grid& lattice, const PointTree& tree, double width);

// Inside (-1) or outside (+1) for every band and ghost voxel (band first, then ghosts). Outside is what
// a flood from the lowest ghost voxel reaches: through ghosts (26-neighbours: the ghost layer is only
// 26-connected in places; it lies a whole band width from the points, so a diagonal step cannot cross
// the surface) and through band voxels farther than `blocked` from the points (6-neighbours: a 6-path
// that crosses the surface passes a voxel within h/2 of it, which is within `blocked` of a point). Band
// voxels nearer the points take the side of their nearest labelled neighbours.
std::vector<signed char> label_sides(const Grid& lattice, const SegmentationDomain& d, double blocked,
                                     std::int64_t& inside_band);

}  // namespace poreshell
