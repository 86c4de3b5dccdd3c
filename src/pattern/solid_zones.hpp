#pragma once
// Where the wall must stay solid: a rim along the open boundary of a sheet (a cast's edge) and
// keep-out spheres and boxes. They act inside the model, as a local mean concentration phi_bar(x) raised to
// the solid phase -1, so the pattern arranges itself around them instead of being cut afterwards.

#include <array>
#include <span>
#include <vector>

#include "band/band.hpp"
#include "geometry/mesh.hpp"

namespace poreshell {

using Segment = std::array<Vec3, 2>;

struct KeepOutSphere {
  Vec3 center = Vec3::Zero();
  double radius = 0.0;
};

struct KeepOutBox {
  Vec3 min = Vec3::Zero(), max = Vec3::Zero();  // axis-aligned corners
};

// Edges with exactly one incident triangle (the open boundary), as segments.
std::vector<Segment> boundary_segments(const TriangleMesh& mesh);

// Per band voxel, 1 within `rim` of a boundary segment or inside a keep-out sphere or box, 0 beyond a
// further `ramp`, linear between (all lengths in the band's grid units).
std::vector<double> solid_zone_weight(const NarrowBand& band, std::span<const Segment> boundary, double rim,
                                      std::span<const KeepOutSphere> keep_out, double ramp,
                                      std::span<const KeepOutBox> boxes = {});

// phi_bar(x) = phi_bar + (-1 - phi_bar) w(x): the nonlocal term's target, solid where w = 1.
std::vector<double> mean_concentration_field(std::span<const double> weight, double phi_bar);

}  // namespace poreshell
