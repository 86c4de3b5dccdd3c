#pragma once
// What the solid zones asked for, measured on an output's holes: the rim left along the open boundary
// and each keep-out's clearance (the report's "applied"). Lengths in mm, the output's frame.

#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include "core/types.hpp"
#include "input/placement.hpp"
#include "pattern/solid_zones.hpp"

namespace poreshell {

struct HoleDisc {
  Vec3 centre = Vec3::Zero();  // mm
  double diameter = 0.0;       // mm
};

struct ZoneCheck {
  double rim_asked = 0.0;  // the rim the run applied (ZoneOptions::rim, the default resolved), mm
  // The least distance from a hole's edge (centre distance minus the radius) to the mesh's open
  // boundary; NaN without an open boundary or holes. A rim of R mm is honoured when this is >= R.
  double rim = std::numeric_limits<double>::quiet_NaN();
  // The least distance from a hole's edge to a keep-out sphere or box (negative: a hole reaches into
  // one); NaN without keep-outs or holes. `holes_in_keep_outs` counts the holes that reach in.
  double keep_out_clearance = std::numeric_limits<double>::quiet_NaN();
  std::int64_t holes_in_keep_outs = 0;
};

ZoneCheck check_zones(std::span<const HoleDisc> holes, const ZoneOptions& zones, const PlacedSurface& placed);

}  // namespace poreshell
