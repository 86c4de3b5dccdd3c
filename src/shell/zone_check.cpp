#include "shell/zone_check.hpp"

#include <algorithm>
#include <cmath>

#include "pattern/solid_zones.hpp"

namespace poreshell {

// Holes x boundary segments, brute force: a few hundred holes by a few thousand segments is a few
// milliseconds, beside seconds of meshing.
ZoneCheck check_zones(std::span<const HoleDisc> holes, const Options& options, const PlacedSurface& placed) {
  ZoneCheck check;
  check.rim_asked = options.rim;
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
  if (options.keep_out.empty() && options.keep_out_boxes.empty()) return check;
  double clearance = std::numeric_limits<double>::infinity();
  for (const HoleDisc& h : holes) {
    double nearest = std::numeric_limits<double>::infinity();
    for (const KeepOutSphere& k : options.keep_out)
      nearest = std::min(nearest, (h.centre - vec(k.centre)).norm() - k.radius);
    for (const KeepOutBox& k : options.keep_out_boxes)
      nearest = std::min(nearest, box_distance(h.centre, SolidBox::spanned(vec(k.min), vec(k.max))));
    nearest -= 0.5 * h.diameter;
    if (nearest < 0.0) ++check.holes_in_keep_outs;
    clearance = std::min(clearance, nearest);
  }
  check.keep_out_clearance = clearance;
  return check;
}

}  // namespace poreshell
