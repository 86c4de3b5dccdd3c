#include "shell/zone_check.hpp"

#include <algorithm>
#include <cmath>

namespace poreshell {

// Holes x boundary segments, brute force: a few hundred holes by a few thousand segments is a few
// milliseconds, beside seconds of meshing.
ZoneCheck check_zones(std::span<const HoleDisc> holes, const ZoneOptions& zones,
                      const PlacedSurface& placed) {
  ZoneCheck check;
  check.rim_asked = zones.rim;
  if (holes.empty()) return check;
  if (placed.mesh) {
    std::vector<Segment> boundary = boundary_segments(*placed.mesh);
    for (Segment& s : boundary) s = {placed.to_mm(s[0]), placed.to_mm(s[1])};
    if (!boundary.empty()) {
      double rim = std::numeric_limits<double>::infinity();
      for (const HoleDisc& h : holes)
        for (const Segment& s : boundary)
          rim = std::min(rim, segment_distance(h.centre, s) - 0.5 * h.diameter);
      check.rim = rim;
    }
  }
  if (!zones.any_keep_out()) return check;
  double clearance = std::numeric_limits<double>::infinity();
  for (const HoleDisc& h : holes) {
    double nearest = std::numeric_limits<double>::infinity();
    for (const SolidSphere& k : zones.keep_out)
      nearest = std::min(nearest, (h.centre - k.center).norm() - k.radius);
    for (const SolidBox& k : zones.keep_out_boxes) nearest = std::min(nearest, box_distance(h.centre, k));
    nearest -= 0.5 * h.diameter;
    if (nearest < 0.0) ++check.holes_in_keep_outs;
    clearance = std::min(clearance, nearest);
  }
  check.keep_out_clearance = clearance;
  return check;
}

}  // namespace poreshell
