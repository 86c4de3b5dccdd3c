// The public API's estimate(): a run's size, cost and sanity before it runs, from the input placed on
// its grid and the band counted on a grid 8 times coarser (band/memory_estimate.hpp). The time and
// output constants are fitted to runs on the development machine (docs/benchmarks.md).

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <variant>

#include "core/error.hpp"
#include "core/units.hpp"
#include "geometry/refine.hpp"
#include "input/placement.hpp"
#include "pattern/hole_map.hpp"
#include "pattern/solid_zones.hpp"
#include "pipeline/pipeline.hpp"
#include "pipeline/run_cost.hpp"
#include "pipeline/solve_stage.hpp"
#include "pipeline/validate.hpp"
#include "poreshell/poreshell.hpp"
#include "shell/shell.hpp"

namespace poreshell {
namespace {

// Thresholds of the warnings: the size a print usually has, and a cost worth a second thought.
constexpr double kSmallModelMm = 5.0, kLargeModelMm = 3000.0;
constexpr double kLongRunSeconds = 300.0;
constexpr double kLargeOutputBytes = 300e6;
// The thinnest wall most printers make (resin, fine nozzles); filament needs about twice it.
constexpr double kThinWallMm = 0.4;

// "212 million", "85 thousand", "640": a count as a person reads it.
std::string count_in_words(double n) {
  if (n >= 1e9) return fmt::format("{:.3g} billion", n / 1e9);
  if (n >= 1e6) return fmt::format("{:.3g} million", n / 1e6);
  if (n >= 1e4) return fmt::format("{:.0f} thousand", n / 1e3);
  return fmt::format("{:.0f}", n);
}

void size_warnings(const Estimate& e, const Input& input, const Options& o, std::vector<std::string>& out) {
  const double longest_mm = *std::max_element(e.size_mm.begin(), e.size_mm.end());
  if (longest_mm >= kSmallModelMm && longest_mm <= kLargeModelMm) return;
  std::string text = fmt::format("the model is {} mm across, {} than most prints", readable(longest_mm),
                                 longest_mm < kSmallModelMm ? "smaller" : "larger");
  const Unit unit = std::visit([](const auto& in) { return in.unit; }, input);
  const bool shape_in_mm =
      std::holds_alternative<ShapeInput>(input) && std::get<ShapeInput>(input).radius_mm > 0;
  const double longest_units = longest_mm / (millimetres_per(unit) * o.scale);
  const std::optional<Unit> better = shape_in_mm ? std::nullopt : fitting_unit(longest_units, unit);
  if (better && o.scale == 1.0)
    text += fmt::format("; if its coordinates are in {}, say `units` {} ({} mm)", to_string(*better),
                        to_string(*better), readable(longest_units * millimetres_per(*better)));
  else
    text += fmt::format("; `scale` {:.3g} would make it 100 mm", o.scale * 100.0 / longest_mm);
  out.push_back(text);
}

// A keep-out that misses the model keeps nothing solid: most likely its coordinates are in another frame
// or unit (issue 47: one 460 mm away reported success).
void keep_out_warnings(const Options& o, const PlacedSurface& placed, std::vector<std::string>& out) {
  const Box box = placed.surface->bounds();
  const Vec3 low = placed.to_mm(box.min), high = placed.to_mm(box.max);
  const ZoneOptions zones = zone_options(o);
  const std::vector<double> gaps = keep_out_gaps(zones, SolidBox::spanned(low, high));
  const std::string bounds = fmt::format("({:.4g}, {:.4g}, {:.4g}) to ({:.4g}, {:.4g}, {:.4g})", low.x(),
                                         low.y(), low.z(), high.x(), high.y(), high.z());
  for (std::size_t k = 0; k < gaps.size(); ++k)
    if (gaps[k] > 0.0)
      out.push_back(
          fmt::format("{} lies {} mm outside the model's bounds {} and keeps nothing solid; give "
                      "it in the input's frame, in mm",
                      keep_out_name(zones, k), readable(gaps[k]), bounds));
}

// The estimate from the input as the run will place it.
Estimate estimate_prepared(const Input& input, const PreparedInput& prepared) {
  const Options& given = prepared.given;
  const Options& options = prepared.options;
  const std::optional<PatternPlan>& plan = prepared.plan;
  const PlacedSurface& placed = prepared.placed;
  const double mm_per_grid = placed.mm_per_grid();
  Estimate e;
  const Box box = placed.surface->bounds();
  for (int a = 0; a < 3; ++a)
    e.size_mm[static_cast<std::size_t>(a)] = (box.max[a] - box.min[a]) * mm_per_grid;
  e.grid = Grid::fitted(placed.domain, placed.resolution).dims();
  const RunCost cost = estimate_run_cost(prepared, true);
  e.voxel_size_mm = cost.voxel_size_mm;
  e.band_voxels = cost.band_voxels;
  e.seconds = cost.seconds;
  e.peak_bytes = cost.peak_bytes;
  e.triangles = cost.triangles;
  e.stl_bytes = cost.stl_bytes;
  e.preview = options.preview;
  e.ply_bytes = cost.ply_bytes;
  // A wall thinner than printers make is meshed at a third of it: say both before the run (issue 47:
  // `wall` 0.2 was estimated at 212 million triangles without a word).
  if (options.mode == Mode::shell && options.wall > 0.0 && options.wall < kThinWallMm && !options.preview)
    e.warnings.push_back(
        fmt::format("a `wall` of {:.2g} mm is thinner than most printers make ({:.2g} mm and "
                    "up), and is meshed at {:.2g} mm: about {} triangles; ask for a "
                    "thicker `wall`",
                    options.wall, kThinWallMm, cost.shell_mm, count_in_words(cost.triangles)));

  size_warnings(e, input, given, e.warnings);
  // The smallest extent that holes can span: a flat part's thickness (under a tenth of its length) is
  // not one.
  const double longest_mm = *std::max_element(e.size_mm.begin(), e.size_mm.end());
  double smallest_mm = longest_mm;
  for (const double extent : e.size_mm)
    if (extent >= 0.1 * longest_mm) smallest_mm = std::min(smallest_mm, extent);
  const double hole = plan ? plan->diameter : 0.0;
  if (hole > smallest_mm / 3.0)
    e.warnings.push_back(
        fmt::format("holes of {} mm are more than a third of the model's smallest extent ({} mm): few holes "
                    "fit; ask for a smaller `hole_diameter`",
                    readable(hole), readable(smallest_mm)));
  keep_out_warnings(given, placed, e.warnings);
  if (e.seconds > kLongRunSeconds)
    e.warnings.push_back(
        fmt::format("this run may take about {:.0f} minutes; a coarser `resolution` or "
                    "`voxel_size`, or larger holes, make it faster",
                    e.seconds / 60.0));
  if (e.stl_bytes > kLargeOutputBytes && !e.preview)
    e.warnings.push_back(fmt::format("the output may be about {:.0f} MB as STL; `max_triangles` reduces it",
                                     e.stl_bytes / 1e6));
  return e;
}

}  // namespace

Estimate estimate(const Input& input, const Options& options) {
  return estimate_prepared(input, prepare_input(input, options));
}

Estimate estimate(const Prepared& prepared) {
  if (!prepared.input || !prepared.state)
    throw Error(ErrorCode::invalid_option, "estimate: the Prepared was not made by prepare()");
  return estimate_prepared(*prepared.input, *prepared.state);
}

}  // namespace poreshell
