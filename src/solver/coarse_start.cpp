#include "solver/coarse_start.hpp"

#include <tbb/parallel_for.h>

#include <chrono>
#include <cmath>

#include "core/parallel.hpp"
#include "pattern/pattern.hpp"

namespace poreshell {

std::optional<Grid> pattern_grid(const Surface& surface, double h, double epsilon) {
  const double pattern_h = epsilon / epsilon_m(4.0, 1.0);
  if (!(pattern_h >= kCoarseStartMinRatio * h)) return std::nullopt;
  return covering_grid(surface, pattern_h);
}

std::vector<double> coarse_start(const Surface& surface, const Grid& grid, const NarrowBand& fine,
                                 const ModelParameters& model, double dt, const CoarseStartOptions& options,
                                 CoarseLevel& report) {
  const auto start = std::chrono::steady_clock::now();
  BandOptions band_options;
  band_options.progress = options.band_progress;
  const NarrowBand coarse = build_band(surface, grid, band_options);
  LevelStart level = options.start(coarse);
  {
    FastSolver solver(coarse, model, dt, options.fast);
    if (!level.mean_field.empty()) solver.set_mean_field(std::move(level.mean_field));
    RunOptions run = options.run;
    run.tolerance *= kCoarseTolerance;
    if (options.stop) run.stop = options.stop(coarse);
    report.run = run_to_steady_state(solver, level.phi, nullptr, run);
  }
  report.dims = grid.dims();
  report.h = grid.h();
  report.band_voxels = coarse.size();
  report.spots = spot_statistics(coarse, level.phi, 0.0).count;

  // Each fine voxel takes the coarse pattern's value at its closest point. The surface lies inside the
  // coarse band, more than a cell from its edge, so every stencil is complete.
  std::vector<double> phi(fine.size());
  monitored_for(fine.size(), options.carry_progress, [&](std::size_t v) {
    phi[v] = interpolation_stencil(coarse, fine.closest_point(v)).interpolate(level.phi);
  });
  report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return phi;
}

}  // namespace poreshell
