#pragma once
// Triangular patches over a point cloud for the paper's route: densified (Fig. 8), umbrellas for raw
// points, their boundary vertices and caps over their holes.

#include <array>
#include <cstdint>
#include <vector>

#include "core/types.hpp"

namespace poreshell {

using Triangles = std::vector<std::array<std::int32_t, 3>>;

// Fig. 8: splits each triangle's longest edge at its midpoint until every edge is shorter than
// `tolerance`. Returns the input points followed by the new ones, exact duplicates removed (a shared
// edge is split at the same midpoint from both sides). Throws InputError past `max_points`.
std::vector<Vec3> densify_patches(const std::vector<Vec3>& points, const Triangles& triangles,
                                  double tolerance, std::size_t max_points = 50'000'000);

// Patches for raw points, which have none: each point's umbrella, the triangles between it and
// consecutive nearest neighbours ordered by angle in its tangent plane (PCA), leaving out gaps wider
// than 120 degrees (borders). Duplicates removed.
// Marks in `boundary` the points with such a gap.
Triangles umbrella_patches(const std::vector<Vec3>& points, std::vector<char>* boundary = nullptr,
                           int neighbors = 8);

// Vertices on edges that only one triangle uses.
std::vector<char> boundary_vertices(std::size_t points, const Triangles& triangles);

// Closes holes, which the segmentation cannot tell from the outside: boundary points closer than five
// sample spacings form a rim; each rim of at least `min_points` gets a fan of triangles from its
// centroid (appended to `points`) over the rim ordered by angle in its best-fit plane. Returns the
// number of caps. Not in the paper, which assumes a closed surface.
int cap_holes(std::vector<Vec3>& points, Triangles& triangles, const std::vector<char>& boundary,
              std::size_t min_points);

}  // namespace poreshell
