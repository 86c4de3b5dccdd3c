// Google Benchmark micro-benchmarks: one band build, one time step of each solver and one multigrid
// V-cycle, on the sphere of section 3.2 (N = 131, alpha 1400, eps_4, dt = 100 h).

#include <benchmark/benchmark.h>

#include "band/band.hpp"
#include "solver/band_multigrid.hpp"
#include "solver/fast_solver.hpp"
#include "solver/initial_condition.hpp"
#include "solver/reference_solver.hpp"

using namespace poreshell;

namespace {

struct PaperSphere {
  std::unique_ptr<Surface> surface = make_paper_shape("sphere");
  Grid grid{Vec3::Zero(), 1.0 / 130, {131, 131, 131}};
  NarrowBand band = build_band(*surface, grid);
  ModelParameters model{1400, epsilon_m(4, 1.0 / 130), -0.3};
  double dt = 100.0 / 130;
};

const PaperSphere& sphere() {
  static const PaperSphere s;
  return s;
}

void BM_BandBuild(benchmark::State& state) {
  const PaperSphere& s = sphere();
  for (auto _ : state) benchmark::DoNotOptimize(build_band(*s.surface, s.grid).size());
  state.counters["band_voxels"] = static_cast<double>(s.band.size());
}

// A step well into the run (after 30 steps), where the pattern has formed.
template <class MakeSolver>
void time_steps(benchmark::State& state, const MakeSolver& make) {
  const PaperSphere& s = sphere();
  auto solver = make(s);
  std::vector<double> phi = random_initial_condition(s.band, -0.3, 0.5, 1);
  for (int n = 0; n < 30; ++n) solver->step(phi);
  double inner = 0;
  for (auto _ : state) inner += solver->step(phi).inner_iterations;
  state.counters["inner_per_step"] = inner / static_cast<double>(state.iterations());
  state.counters["band_voxels"] = static_cast<double>(s.band.size());
}

void BM_FastStep(benchmark::State& state) {
  time_steps(state, [](const PaperSphere& s) { return std::make_unique<FastSolver>(s.band, s.model, s.dt); });
}

void BM_ReferenceStep(benchmark::State& state) {
  time_steps(state,
             [](const PaperSphere& s) { return std::make_unique<ReferenceSolver>(s.band, s.model, s.dt); });
}

void BM_MultigridSetup(benchmark::State& state) {
  const PaperSphere& s = sphere();
  for (auto _ : state) benchmark::DoNotOptimize(BandMultigrid(s.band, 700.0).level_count());
}

void BM_VCycle(benchmark::State& state) {
  const PaperSphere& s = sphere();
  const double z = 700.0;  // the small shift of the fast solver at these parameters
  BandMultigrid mg(s.band, z);
  std::vector<double> b = random_initial_condition(s.band, 0.0, z, 3), x(s.band.size(), 0.0);
  for (auto _ : state) benchmark::DoNotOptimize(mg.solve(z, b, x, 0.0, 1).residual);
}

}  // namespace

BENCHMARK(BM_BandBuild)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_MultigridSetup)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_VCycle)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_FastStep)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ReferenceStep)->Unit(benchmark::kMillisecond)->Iterations(3);

BENCHMARK_MAIN();
