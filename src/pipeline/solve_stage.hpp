#pragma once
// The solve stage: the model on this grid (the paper's parameters or the hole map's), the initial
// state (noise, the even layout's discs, or the coarse start's carried pattern), and the run to the
// steady state. It orders the solver's parts with the pattern's (the layout, the solid zones), so it
// lives with the pipeline: solver/ holds the numerics alone.

#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "band/band.hpp"
#include "core/run_monitor.hpp"
#include "input/placement.hpp"
#include "pattern/hole_map.hpp"
#include "poreshell/options.hpp"
#include "solver/coarse_start.hpp"
#include "solver/hole_stop.hpp"
#include "solver/model.hpp"
#include "solver/time_stepping.hpp"

namespace poreshell {

// What the solve stage is asked for: the request's share for it, the automatic choices made. Filled
// field by field by solve_options() (pipeline/stage_options.hpp): no defaults of its own, so that
// Options' are the only ones.
struct SolveOptions {
  // The paper's model, eq. (2.1), where no hole plan gives one.
  double alpha{}, epsilon_m{}, dt_h{}, phi_bar{};
  double initial_amplitude{};  // of the starting noise about phi_bar
  std::uint64_t seed{};
  double level{};  // the first pore level: the holes rule counts holes there
  bool preview{};
  Layout layout{};     // never automatic
  StopRule stop{};     // never automatic
  double tolerance{};  // the paper's rule: e_c below it
  int max_steps{};
  int energy_every{};
  SolverKind solver{};
  double fast_tolerance{}, min_stabilisation{};
  bool coarse_start{};
  InnerIteration inner{};  // the reference solver's
  double inner_tolerance{};
};

// What a solve made and how, as the report gives it (PipelineResult holds one).
struct SolveSummary {
  ModelParameters model;
  double dt = 0.0;
  std::string solver_name, inner_iteration;
  RunResult run;                            // on the given grid
  std::optional<CoarseLevel> coarse_start;  // the run on the pattern's grid before it, if any
  std::size_t solver_bytes = 0;             // the solver's own arrays
  StopRule stop_rule = StopRule::paper;     // the rule that ended the run (never automatic)
  Layout layout = Layout::paper;            // never automatic
  std::int64_t layout_holes = 0;            // cvt: the discs the run started from
};

// The summary and the fields the later stages take over.
struct SolveResult : SolveSummary {
  std::vector<double> phi;          // on the band, at the end
  std::vector<double> zone_weight;  // per band voxel, how solid (empty: no zones)
};

// The holes rule's settings for this run (docs/solver.md "Stop rules").
HoleStopOptions hole_stop_options(const SolveOptions& options, double min_spread);

// Per band voxel how solid the wall must stay (pattern/solid_zones.hpp), for a band and epsilon.
using SolidZones = std::function<std::vector<double>(const NarrowBand&, double epsilon)>;

// The model for this grid: the hole map's (epsilon from the spacing, dt from epsilon^2) when `plan` is
// set, else the paper's (epsilon_m from h, dt = K h).
void choose_model(const SolveOptions& options, const std::optional<PatternPlan>& plan, double mm_per_grid,
                  double h, ModelParameters& model, double& dt);

SolveResult solve_pattern(const SolveOptions& options, const std::optional<PatternPlan>& plan,
                          const PlacedSurface& placed, const Grid& grid, const NarrowBand& band,
                          const SolidZones& zones, RunMonitor& monitor);

}  // namespace poreshell
