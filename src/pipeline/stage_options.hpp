#pragma once
// The request (Options) resolved into each stage's own options, once: a stage reads only its struct
// (issue 48, item 1). The automatic choices (the layout, the stop rule) are made here, not in the stage.

#include "input/placement.hpp"
#include "pattern/solid_zones.hpp"
#include "pipeline/solve_stage.hpp"
#include "poreshell/options.hpp"

namespace poreshell {

// Whether holes are asked in mm (the hole map's route) rather than by the paper's parameters.
inline bool holes_in_mm(const Options& o) {
  return o.hole_diameter > 0.0 || o.spacing > 0.0 || o.porosity > 0.0;
}

// The layout a run makes: Options::layout, with automatic resolved (cvt for holes in mm).
Layout resolve_layout(const Options& options, bool holes_in_mm);

// The rule a run stops by: Options::stop, with automatic resolved (holes for a preview and for the
// even layout, else the paper's).
StopRule resolve_stop_rule(const Options& options, Layout layout);

// The input's placement's share of the request.
PlacementOptions placement_options(const Options& options);

// The solid zones' share of the request (the rim, the keep-outs, the thin-part and crease thresholds),
// for the rooms that make and check them.
ZoneOptions zone_options(const Options& options);

// The solve's share, for a run with a hole plan (`planned`) or on the paper's parameters.
SolveOptions solve_options(const Options& options, bool planned);

}  // namespace poreshell
