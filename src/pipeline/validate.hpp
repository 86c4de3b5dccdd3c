#pragma once
// The options' checks that need more than one stage: against each other (validate(), public) and
// with the grid and wall they lead to. Each stage checks its own arguments as well.

#include "input/placement.hpp"
#include "pattern/hole_map.hpp"
#include "poreshell/options.hpp"

namespace poreshell {

// The voxel size for a hole plan: the plan's, or the one asked for when it keeps the pattern's interface
// resolved. Throws OptionError(voxel_size) for a coarser one.
double choose_voxel_size(double asked, const PatternPlan& plan);

// A reduction bound that could let the reduced wall's sides meet is refused (the default reduces too).
void check_reduction(const Options& options, double wall_mm);
// Options::max_deviation's default, mm (issue 49): a bound on the reduced output's distance from the full
// isosurface that no print notices, or a quarter of the wall where that is less (a model a few
// millimetres across), so that the default never refuses a run.
inline constexpr double kDefaultMaxDeviation = 0.02;
// The output's reduction bound in mm: max_deviation, the default no more than a quarter of the wall.
double reduction_bound(const Options& options, double wall_mm);
// x rounded down to three significant digits, so that advice of "at most" it holds when followed.
double rounded_down(double x);

}  // namespace poreshell
