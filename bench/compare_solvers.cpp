// Runs the whole pipeline (input file in -> STL out) once per solver in one process, on the same
// machine and inputs, and prints each stage's time, the steps, the pattern and the ratio of the solve
// and total times. Usage: bench_compare --mesh data/stanford-bunny.obj --alpha 2200 [--solvers ...].

#include <fmt/core.h>

#include <CLI/CLI.hpp>
#include <filesystem>
#include <string>
#include <vector>

#include "poreshell/pipeline.hpp"

int main(int argc, char** argv) {
  poreshell::PipelineConfig config;
  std::string mesh, out_dir = "out/bench";
  std::vector<std::string> solvers{"reference", "fast"};
  CLI::App app{"poreshell solver comparison: same input, same process, one run per solver"};
  app.add_option("--shape", config.shape);
  app.add_option("--mesh", mesh);
  app.add_option("--resolution", config.resolution);
  app.add_option("--alpha", config.alpha);
  app.add_option("--seed", config.seed);
  app.add_option("--iso", config.iso_levels)->delimiter(',');
  app.add_option("--solvers", solvers)->delimiter(',');
  app.add_option("--out-dir", out_dir);
  CLI11_PARSE(app, argc, argv);
  config.mesh = mesh;
  config.energy_every = 0;  // the energy's factorisation is a diagnostic, not part of the job
  std::filesystem::create_directories(out_dir);
  const std::string name = mesh.empty() ? config.shape : std::filesystem::path(mesh).stem().string();

  std::vector<poreshell::PipelineResult> results;
  for (const std::string& solver : solvers) {
    config.solver = solver;
    config.output = std::filesystem::path(out_dir) / (name + "-" + solver + ".stl");
    results.push_back(poreshell::run_pipeline(config));
    const poreshell::PipelineResult& r = results.back();
    fmt::print(
        "{:<10} {} grid {}x{}x{}, {} band voxels: input {:.2f} s, band {:.2f} s, solve {:.2f} s ({} steps, "
        "{:.4f} s/step), mesh+write {:.2f} s, total {:.2f} s; {} spots, size CV {:.3f}, spacing CV {:.3f}\n",
        solver, name, r.grid_dims[0], r.grid_dims[1], r.grid_dims[2], r.band_voxels, r.seconds_input,
        r.seconds_band, r.seconds_solve, r.run.steps, r.seconds_solve / std::max(1, r.run.steps),
        r.seconds_mesh, r.seconds_total, r.spots.count, r.spots.size_cv, r.spots.spacing_cv);
    std::fflush(stdout);
  }
  if (results.size() == 2)
    fmt::print("ratio {} / {}: solve {:.1f}x, total {:.1f}x\n", solvers[0], solvers[1],
               results[0].seconds_solve / results[1].seconds_solve,
               results[0].seconds_total / results[1].seconds_total);
  return 0;
}
