#pragma once
// The solved pattern made printable before it is meshed: spots too small to print, oblong spots and
// spots that would reach into the rim made solid or cut round (issues 19 and 51). The thresholds are
// print policy, measured on scans; they live here, beside the rules, not in the pipeline.

#include <cstdint>
#include <span>

#include "band/band.hpp"
#include "input/placement.hpp"
#include "pattern/hole_map.hpp"

namespace poreshell {

struct SpotRuleCounts {
  std::int64_t closed_small = 0;    // under the least printable share of the asked diameter
  std::int64_t rounded_oblong = 0;  // cut down to a disc about their centre
  std::int64_t closed_oblong = 0;   // too little left once cut round
  std::int64_t closed_in_rim = 0;   // would leave less than the rim asked
};

// `unevolved`: a preview's layout discs as placed (no equation run), judged by the preview's share.
// `rim_mm`: the solid rim along an open mesh's outline; 0 lets spots there keep their shape (notches).
SpotRuleCounts apply_spot_rules(const NarrowBand& band, std::span<double> phi, const PatternPlan& plan,
                                const PlacedSurface& placed, double rim_mm, bool unevolved);

}  // namespace poreshell
