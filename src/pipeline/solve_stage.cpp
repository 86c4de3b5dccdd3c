#include "pipeline/solve_stage.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <numeric>
#include <stdexcept>

#include "core/error.hpp"
#include "core/heap.hpp"
#include "core/units.hpp"
#include "pattern/layout.hpp"
#include "pattern/pattern.hpp"
#include "pattern/solid_zones.hpp"
#include "solver/energy.hpp"
#include "solver/fast_solver.hpp"
#include "solver/initial_condition.hpp"
#include "solver/reference_solver.hpp"

namespace poreshell {
namespace {

// The solve's share done, for progress: how far e_c has come down from its first value towards the
// tolerance (in log scale), or the share of the step budget used, whichever is further.
double solve_fraction(double first_ec, double ec, double tolerance, int step, int max_steps) {
  double by_ec = 0.0;
  if (first_ec > tolerance && ec > 0.0)
    by_ec = std::clamp(std::log(first_ec / ec) / std::log(first_ec / tolerance), 0.0, 1.0);
  return std::max(by_ec, static_cast<double>(step) / max_steps);
}

}  // namespace

namespace {

// The even layout's start: discs at a centroidal Voronoi tessellation of the surface's free area
// (pattern/layout.hpp), none whose pore would come within half an interface width of an open edge,
// sized so that the pore level's contour is the asked diameter; for a run, on the mean the equation's
// start had (the nonlocal term has a solution only for the mean it starts from). A preview (no mean: the
// discs are shown, not solved) merges overlapping discs as the equation would.
std::vector<double> even_layout_start(const PatternPlan& plan, const PlacedSurface& placed,
                                      const NarrowBand& band, std::span<const double> weight,
                                      std::uint64_t seed, std::optional<double> mean, SolveResult& result) {
  const double epsilon = result.model.epsilon, mm_per_grid = placed.mm_per_grid();
  const double pore_radius = 0.5 * plan.diameter / mm_per_grid;
  std::vector<Vec3> centres = clear_of_open_edges(
      even_layout(band, *placed.surface, weight, plan.spacing / mm_per_grid, seed),
      placed.mesh ? boundary_segments(*placed.mesh) : std::vector<Segment>{}, pore_radius + 0.5 * epsilon);
  if (!mean) centres = merge_overlapping_centres(std::move(centres), 2.0 * pore_radius, *placed.surface);
  result.layout_holes = static_cast<std::int64_t>(centres.size());
  // A run that would write a part without holes, asked for holes, says so instead (issue 47).
  if (centres.empty())
    throw OptionError(
        "hole_diameter",
        fmt::format("no hole of {:.3g} mm at {:.3g} mm spacing fits on the surface's free part: open "
                    "edges, rims, keep-outs, creases and parts thinner than `thin_feature_ratio` "
                    "holes stay solid; ask for smaller `hole_diameter` and `spacing`, or less "
                    "solid (`thin_feature_ratio` 0 keeps no thin part solid)",
                    plan.diameter, plan.spacing));
  // tanh((R - r) / (sqrt 2 eps)) = level at r = D / 2.
  const double radius = pore_radius + std::sqrt(2.0) * epsilon * std::atanh(plan.level);
  return disc_field(band, centres, radius, epsilon, weight, mean);
}

}  // namespace

HoleStopOptions hole_stop_options(const SolveOptions& c, double min_spread) {
  HoleStopOptions o;
  o.level = c.level;
  o.min_spread = min_spread;
  return o;
}

void choose_model(const SolveOptions& c, const std::optional<PatternPlan>& plan, double mm_per_grid, double h,
                  ModelParameters& model, double& dt) {
  if (!plan) {
    model = ModelParameters{c.alpha, epsilon_m(c.epsilon_m, h), c.phi_bar};
    dt = c.dt_h * h;
    return;
  }
  const HoleCalibration& cal = hole_calibration();
  const double eps = plan->epsilon / mm_per_grid;
  model = ModelParameters{cal.kappa / (eps * eps), eps, plan->phi_bar};
  dt = cal.dt_per_epsilon_squared * eps * eps;
}

SolveResult solve_pattern(const SolveOptions& c, const std::optional<PatternPlan>& plan,
                          const PlacedSurface& placed, const Grid& grid, const NarrowBand& band,
                          const SolidZones& zones, RunMonitor& monitor) {
  SolveResult result;
  choose_model(c, plan, placed.mm_per_grid(), grid.h(), result.model, result.dt);
  // The initial state on a band: noise about phi_bar, solid zones (rims along open boundaries, keep-out
  // spheres and masks) solid and held there by a local mean concentration. Without noise: the mean
  // field alone, for a band that starts from a carried pattern.
  const auto zone_weight = [&](const NarrowBand& b) {
    return zones ? zones(b, result.model.epsilon) : std::vector<double>{};
  };
  const auto level_start = [&](const NarrowBand& b, std::span<const double> weight, bool noise) {
    LevelStart s;
    if (!weight.empty()) s.mean_field = mean_concentration_field(weight, result.model.phi_bar);
    if (!noise) return s;
    s.phi = random_initial_condition(b, result.model.phi_bar, c.initial_amplitude, c.seed);
    for (std::size_t v = 0; v < weight.size(); ++v) s.phi[v] = (1.0 - weight[v]) * s.phi[v] - weight[v];
    return s;
  };
  RunOptions run_options;
  run_options.max_steps = c.max_steps;
  run_options.tolerance = c.tolerance;
  run_options.energy_every = c.energy_every;
  // Separated phases span about [-1, 1]; the decayed noise of the quiet phase spans far less.
  if (uniform_state_unstable(result.model.alpha, result.model.epsilon, result.model.phi_bar))
    run_options.min_spread = 1.0;
  result.layout = c.layout;
  result.stop_rule = c.stop;
  const bool holes_rule = result.stop_rule == StopRule::holes;
  std::shared_ptr<HoleStop> current_stop;  // the holes rule of the run under way
  const auto make_stop = [&](const NarrowBand& b) {
    current_stop = std::make_shared<HoleStop>(b, hole_stop_options(c, run_options.min_spread));
    return [stop = current_stop](int step, std::span<const double> phi) { return stop->settled(step, phi); };
  };
  double first_ec = 0.0;
  // The stage's share the current run's steps fill (with a coarse start: its run, then the fine one).
  double share_begin = 0.0, share_end = 1.0;
  const auto report_step = [&](const StepProgress& p) {
    if (p.step == 1) first_ec = p.ec;
    char energy[48] = "";
    if (!std::isnan(p.energy)) std::snprintf(energy, sizeof energy, "  energy %.6e", p.energy);
    char holes[96] = "";
    if (current_stop && current_stop->last_check().step == p.step) {
      const HoleStopCheck& h = current_stop->last_check();
      std::snprintf(holes, sizeof holes, "  holes %lld shift %.3f flipped %.1e",
                    static_cast<long long>(h.holes), h.shift, h.flipped);
    }
    char line[256];
    std::snprintf(line, sizeof line, "%sstep %5d  e_c %.3e%s  inner %lld iterations%s%s",
                  p.coarse ? "coarse " : "", p.step, p.ec, energy,
                  static_cast<long long>(p.inner.inner_iterations),
                  p.inner.converged ? "" : " (not converged)", holes);
    // Every step is reported (a step takes milliseconds to seconds); the front end chooses what to show.
    const double f = current_stop
                         ? std::max(current_stop->progress(), static_cast<double>(p.step) / c.max_steps)
                         : solve_fraction(first_ec, p.ec, c.tolerance, p.step, c.max_steps);
    monitor.advance(share_begin + f * (share_end - share_begin), line, p.step, true);
  };
  run_options.on_step = report_step;
  const bool fast = c.solver == SolverKind::fast;
  const bool even = plan && result.layout == Layout::cvt;
  // The even layout starts from discs on this grid: no pattern to form on a coarser one.
  const std::optional<Grid> coarse_grid = fast && c.coarse_start && !even
                                              ? pattern_grid(*placed.surface, grid.h(), result.model.epsilon)
                                              : std::nullopt;
  // Shares of the stage, from runs of the bunny: with a coarse start its band, set-up, run and carry take
  // about half, the fine set-up a few percent, the fine run the rest.
  const double fine_setup = coarse_grid ? 0.5 : 0.0, fine_steps = fine_setup + 0.05;
  result.zone_weight = zone_weight(band);
  const std::vector<double>& fine_weight = result.zone_weight;
  // A preview of the even layout solves nothing: no noise to start from.
  LevelStart fine_start = level_start(band, fine_weight, !coarse_grid && !(even && c.preview));
  if (even) {
    std::optional<double> mean;
    if (!c.preview)
      mean = std::accumulate(fine_start.phi.begin(), fine_start.phi.end(), 0.0) /
             static_cast<double>(fine_start.phi.size());
    fine_start.phi = even_layout_start(*plan, placed, band, fine_weight, c.seed, mean, result);
    // A preview's holes are these discs: the equation would only round them (issue 18: a second).
    if (c.preview) {
      result.phi = std::move(fine_start.phi);
      return result;
    }
  }
  // A layer has no ghosts and -1 for its outer neighbours: the solvers would read and write past it.
  if (band.surface_layer())
    throw std::logic_error("solve_pattern: the band is a surface layer (builds_surface_layer), not solvable");
  monitor.check();
  if (coarse_grid) {
    CoarseStartOptions coarse{[&](const NarrowBand& b) { return level_start(b, zone_weight(b), true); },
                              run_options,
                              {},
                              {},
                              {},
                              {}};
    coarse.band_progress = StageProgress(monitor, 0.0, 0.05);
    coarse.fast.progress = StageProgress(monitor, 0.05, 0.08);
    coarse.fast.cycles = StageProgress(monitor, 0.0, 0.0);
    coarse.carry_progress = StageProgress(monitor, 0.48, 0.5);
    share_begin = 0.08;
    share_end = 0.48;
    coarse.fast.tolerance = c.fast_tolerance;
    coarse.fast.min_stabilisation = c.min_stabilisation;
    coarse.run.energy_every = 0;
    if (holes_rule) coarse.stop = make_stop;
    coarse.run.on_step = [&](const StepProgress& p) {
      StepProgress tagged = p;
      tagged.coarse = true;
      report_step(tagged);
    };
    result.coarse_start.emplace();
    fine_start.phi = coarse_start(*placed.surface, *coarse_grid, band, result.model, result.dt, coarse,
                                  *result.coarse_start);
    release_free_memory();
  }
  std::vector<double>& phi = fine_start.phi;
  std::unique_ptr<TimeStepper> solver;
  if (!fast) {
    InnerOptions inner;
    inner.method = c.inner;
    inner.tolerance = c.inner_tolerance;
    solver = std::make_unique<ReferenceSolver>(band, result.model, result.dt, inner);
    result.inner_iteration = to_string(c.inner);
  } else {
    FastOptions options;
    options.tolerance = c.fast_tolerance;
    options.min_stabilisation = c.min_stabilisation;
    options.progress = StageProgress(monitor, fine_setup, fine_steps);
    options.cycles = StageProgress(monitor, 0.0, 0.0);
    auto solver_fast = std::make_unique<FastSolver>(band, result.model, result.dt, options);
    if (!fine_start.mean_field.empty()) solver_fast->set_mean_field(std::move(fine_start.mean_field));
    result.solver_bytes = solver_fast->memory_bytes();
    solver = std::move(solver_fast);
    result.inner_iteration = "multigrid";
  }
  monitor.check();
  share_begin = fine_steps;
  share_end = 1.0;
  result.solver_name = solver->name();
  // The energy's Poisson factorisation costs about 6 s at 73k band voxels and 70 s / 2 GB at 290k:
  // energy_every 0 skips it for large runs.
  std::optional<EnergyFunctional> energy;
  if (c.energy_every > 0) energy.emplace(band, result.model);
  if (holes_rule) run_options.stop = make_stop(band);
  result.run = run_to_steady_state(*solver, phi, energy ? &*energy : nullptr, run_options);
  // The solver's hierarchy and the energy's factorisation are done with: free them before meshing,
  // the stage with the largest footprint.
  solver.reset();
  energy.reset();
  release_free_memory();
  if (!std::isfinite(result.run.final_ec))
    throw Error(ErrorCode::internal, "the solver diverged (non-finite values); please report this as a bug");
  result.phi = std::move(phi);
  return result;
}

}  // namespace poreshell
