#pragma once
// Coarse start for patterns whose interface spans many voxels (pores in millimetres on a fine grid,
// docs/solver.md "Coarse start"). The pattern's length scales are set by epsilon, not by h: on a grid
// where epsilon spans the paper's eps_4 (about 4 cells) the same model forms the same pattern. So the
// long part of the run (the spinodal phase and the slow relaxation after it, hundreds of steps) is solved
// there, and the result is carried to the fine band by closest points (a band value stands for the value
// at its closest point), where the fine run only relaxes the coarse grid's discretisation error: about a
// dozen steps on the bunny instead of hundreds.

#include <functional>
#include <optional>
#include <vector>

#include "band/band.hpp"
#include "solver/fast_solver.hpp"
#include "solver/model.hpp"
#include "solver/time_stepping.hpp"

namespace poreshell {

// A fine grid about twice as fine as the pattern's or finer starts coarse: the coarse band then has a
// quarter of the voxels or fewer. 1.8, not 2: half the hole map's voxel size, rounded to whole cells
// along the model, comes out a little under 2.
inline constexpr double kCoarseStartMinRatio = 1.8;

// The grid on which epsilon spans eps_4, around `surface`; nothing when the fine spacing h is within
// kCoarseStartMinRatio of it (the fine grid is the pattern's own).
std::optional<Grid> pattern_grid(const Surface& surface, double h, double epsilon);

// What the coarse run needs that depends on the band: the initial phi and the mean concentration per
// voxel (empty: the model's phi_bar everywhere).
struct LevelStart {
  std::vector<double> phi;
  std::vector<double> mean_field;
};

struct CoarseStartOptions {
  std::function<LevelStart(const NarrowBand&)> start;
  RunOptions run;  // the coarse run's; its tolerance is tightened (kCoarseTolerance)
  FastOptions fast;
  // The coarse run's own stop rule for its band (RunOptions::stop), when the run is not the paper's.
  std::function<std::function<bool(int, std::span<const double>)>(const NarrowBand&)> stop;
  // Shares of the solve stage: the coarse band, its solver's set-up (fast.progress), its run (the run's
  // on_step reports), the carry to the fine band.
  StageProgress band_progress{}, carry_progress{};
};

// The coarse run ends at this share of the fine run's tolerance. The paper's e_c = 1e-3 is reached in
// the slow tail, where the pattern still drifts by about that much a step: carried from there, the fine
// run kept drifting at e_c ~ 1.05e-3 for 42 steps (bunny, 131 -> 260); from 5e-4, 11 steps.
inline constexpr double kCoarseTolerance = 0.5;

struct CoarseLevel {
  std::array<int, 3> dims{};
  double h = 0.0;
  std::size_t band_voxels = 0;
  RunResult run;
  std::int64_t spots = 0;  // {phi > 0} on the coarse band
  double seconds = 0.0;    // band, solve and carrying
};

// Solves on `grid` and returns the result carried to `fine` (phi per fine band voxel).
std::vector<double> coarse_start(const Surface& surface, const Grid& grid, const NarrowBand& fine,
                                 const ModelParameters& model, double dt, const CoarseStartOptions& options,
                                 CoarseLevel& report);

}  // namespace poreshell
