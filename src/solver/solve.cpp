#include "solver/solve.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <numeric>

#include "core/error.hpp"
#include "core/heap.hpp"
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

StopRule resolve_stop_rule(const Options& c) {
  if (c.stop != StopRule::automatic) return c.stop;
  // The holes rule keeps the count and the sizes but stops while the layout still glides (up to 0.24
  // spacing on the bunny, docs/solver.md "Stop rules"): the preview's default, not yet the full run's.
  return c.preview ? StopRule::holes : StopRule::paper;
}

Layout resolve_layout(const Options& c, bool holes_in_mm) {
  if (c.layout != Layout::automatic) return c.layout;
  return holes_in_mm ? Layout::cvt : Layout::paper;
}

HoleStopOptions hole_stop_options(const Options& c, double min_spread) {
  HoleStopOptions o;
  o.level = c.iso.empty() ? 0.0 : c.iso.front();
  o.min_spread = min_spread;
  return o;
}

void choose_model(const Options& c, const std::optional<PatternPlan>& plan, double mm_per_grid, double h,
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

namespace {

// Lloyd's iterations of the hole centres, over-relaxed (layout.hpp): on the sphere of radius 50 mm with
// 6 mm holes at 10 mm the cell-area CV of the centres settles within 30 (0.0593 at 30, 100 and 300
// iterations for seed 2; docs/solver.md "Layout").
constexpr int kLloydIterations = 30;

// The equation's layout made even: its holes' centres moved by Lloyd's iteration over the surface's
// free area, discs of the holes' size put at them, and the equation run again from there (it keeps the
// centres, and gives the pores their own shape and size).
void relax_to_even_layout(const Options& c, const NarrowBand& band, const Surface& surface,
                          const SolidZones& zones, TimeStepper& solver, const RunOptions& run_options,
                          std::vector<double>& phi, SolveResult& result) {
  const HoleStats holes = hole_statistics(band, phi, c.iso.front());
  const HoleStats discs = hole_statistics(band, phi, 0.0);  // the phases' own boundary
  if (holes.holes.size() < 2 || discs.holes.empty()) return;
  std::vector<Vec3> centres;
  for (const BandHole& h : holes.holes) centres.push_back(h.centre);
  const std::vector<double> weight = zones ? zones(band, result.model.epsilon) : std::vector<double>{};
  centres = lloyd_centres(std::move(centres), area_samples(band, weight), surface, kLloydIterations);
  result.layout_holes = static_cast<int>(centres.size());
  const double mean = std::accumulate(phi.begin(), phi.end(), 0.0) / static_cast<double>(phi.size());
  phi = disc_field(band, centres, 0.5 * discs.diameter_mean, result.model.epsilon, weight, mean);
  const RunResult first = result.run;
  solver.restart();
  result.run = run_to_steady_state(solver, phi, nullptr, run_options);
  result.layout_steps = result.run.steps;

  result.run.steps += first.steps;
  result.run.inner_iterations += first.inner_iterations;
  result.run.repeated_steps += first.repeated_steps;
  result.run.energy_first = first.energy_first;
}

}  // namespace

SolveResult solve_pattern(const Options& c, const std::optional<PatternPlan>& plan,
                          const PlacedSurface& placed, const Grid& grid, const NarrowBand& band,
                          const SolidZones& zones, RunMonitor& monitor) {
  SolveResult result;
  choose_model(c, plan, placed.mm_per_grid(), grid.h(), result.model, result.dt);
  // The initial state on a band: noise about phi_bar, solid zones (rims along open boundaries, keep-out
  // spheres and masks) solid and held there by a local mean concentration. Without noise: the mean
  // field alone, for a band that starts from a carried pattern.
  const auto level_start = [&](const NarrowBand& b, bool noise) {
    LevelStart s;
    const std::vector<double> weight = zones ? zones(b, result.model.epsilon) : std::vector<double>{};
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
  result.stop_rule = resolve_stop_rule(c);
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
  const std::optional<Grid> coarse_grid =
      fast && c.coarse_start ? pattern_grid(*placed.surface, grid.h(), result.model.epsilon) : std::nullopt;
  // Shares of the stage, from runs of the bunny: with a coarse start its band, set-up, run and carry take
  // about half, the fine set-up a few percent, the fine run the rest.
  const double fine_setup = coarse_grid ? 0.5 : 0.0, fine_steps = fine_setup + 0.05;
  LevelStart fine_start = level_start(band, !coarse_grid);
  monitor.check();
  if (coarse_grid) {
    CoarseStartOptions coarse{
        [&](const NarrowBand& b) { return level_start(b, true); }, run_options, {}, {}, {}, {}};
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
  result.layout = resolve_layout(c, plan.has_value());
  if (result.layout == Layout::cvt) {
    if (holes_rule) run_options.stop = make_stop(band);  // a fresh window
    relax_to_even_layout(c, band, *placed.surface, zones, *solver, run_options, phi, result);
  }
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
