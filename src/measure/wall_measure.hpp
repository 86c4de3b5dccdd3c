#pragma once
// The wall thickness of a solid as written, measured on its mesh: from a point inside the wall, the
// distance to the mesh along +n and along -n (the first crossing of a ray each way), summed. What a
// caliper across the wall would read.

#include <span>

#include "geometry/mesh.hpp"

namespace poreshell {

struct WallProbe {
  Vec3 start = Vec3::Zero();    // inside the solid wall
  Vec3 normal = Vec3::UnitZ();  // unit, across the wall
};

// The median is what the wall is; the 5th to 95th percentiles how evenly it came out. The extremes
// show where probes met a pore's rim (its facets stand a fraction of a cell into the bridge beside
// it), a fold of the model, or a part thinner than two walls, where the wall's two sides merge into
// solid: those probes read several walls and are counted as `merged`.
struct WallMeasurement {
  std::size_t probes = 0;  // probes that met the surface on both sides
  double median = 0.0, min = 0.0, max = 0.0;
  double low = 0.0, high = 0.0;  // 5th and 95th percentiles
  std::size_t merged = 0;        // probes over kMergedWall times the median
};

// A probe reading this many medians crossed more than a wall: solid where the part is thinner than two.
inline constexpr double kMergedWall = 1.5;

WallMeasurement measure_wall(const TriangleMesh& solid, std::span<const WallProbe> probes, double max_length);

}  // namespace poreshell
