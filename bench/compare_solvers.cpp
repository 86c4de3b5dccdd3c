// Runs the whole pipeline (input file in -> STL out) once per solver and seed in one process, on the same
// machine and inputs, and prints each stage's time, the steps, the pattern, the ratio of the solve and
// total times and, over several seeds, the mean pattern statistics of each solver.
// Usage: bench_compare --mesh data/stanford-bunny.obj --alpha 2200 [--solvers ...] [--seeds 1,2,3].

#include <fmt/core.h>

#include <CLI/CLI.hpp>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "io/mesh_writers.hpp"
#include "pipeline/pipeline.hpp"
#include "poreshell/io.hpp"

int main(int argc, char** argv) {
  poreshell::Options config;
  std::string shape = "sphere", mesh, out_dir = "out/bench";
  std::vector<std::string> solvers{"reference", "fast"};
  std::vector<std::uint64_t> seeds{1};
  CLI::App app{"poreshell solver comparison: same input, same process, one run per solver"};
  app.add_option("--shape", shape);
  app.add_option("--mesh", mesh);
  app.add_option("--resolution", config.resolution);
  app.add_option("--alpha", config.alpha);
  app.add_option("--seeds", seeds)->delimiter(',');
  app.add_option("--iso", config.iso)->delimiter(',');
  app.add_option("--solvers", solvers)->delimiter(',');
  app.add_option("--out-dir", out_dir);
  CLI11_PARSE(app, argc, argv);
  const poreshell::Input input =
      mesh.empty() ? poreshell::Input(shape == "torus" ? poreshell::torus() : poreshell::sphere())
                   : poreshell::Input(poreshell::load_mesh(mesh));
  config.energy_every = 0;  // the energy's factorisation is a diagnostic, not part of the job
  std::filesystem::create_directories(out_dir);
  const std::string name = mesh.empty() ? shape : std::filesystem::path(mesh).stem().string();

  struct Totals {
    double solve = 0, total = 0, spots = 0, size_cv = 0, spacing_cv = 0;
  };
  std::vector<Totals> totals(solvers.size());
  for (std::uint64_t seed : seeds)
    for (std::size_t s = 0; s < solvers.size(); ++s) {
      config.solver =
          solvers[s] == "reference" ? poreshell::SolverKind::reference : poreshell::SolverKind::fast;
      config.seed = seed;
      const poreshell::PipelineResult r = poreshell::run_pipeline(input, config, poreshell::unmonitored());
      poreshell::write_mesh(std::filesystem::path(out_dir) / (name + "-" + solvers[s] + ".stl"),
                            r.meshes.front().mesh);
      fmt::print(
          "{:<10} {} seed {}, grid {}x{}x{}, {} band voxels: input {:.2f} s, band {:.2f} s, solve {:.2f} s "
          "({} "
          "steps, {:.4f} s/step), mesh+write {:.2f} s, total {:.2f} s; peak RSS after solve {:.0f} MiB; {} "
          "spots, "
          "size CV {:.3f}, spacing CV {:.3f}\n",
          solvers[s], name, seed, r.grid_dims[0], r.grid_dims[1], r.grid_dims[2], r.band_voxels,
          r.seconds_input, r.seconds_band, r.seconds_solve, r.solve.run.steps,
          r.seconds_solve / std::max(1, r.solve.run.steps), r.seconds_mesh, r.seconds_total,
          static_cast<double>(r.peak_rss_after_solve) / (1024.0 * 1024.0), r.spots.count, r.spots.size_cv,
          r.spots.spacing_cv);
      std::fflush(stdout);
      const double n = static_cast<double>(seeds.size());
      Totals& t = totals[s];
      t.solve += r.seconds_solve;
      t.total += r.seconds_total;
      t.spots += static_cast<double>(r.spots.count) / n;
      t.size_cv += r.spots.size_cv / n;
      t.spacing_cv += r.spots.spacing_cv / n;
    }
  for (std::size_t s = 0; s < solvers.size(); ++s)
    fmt::print("mean over {} seed(s), {:<10}: spots {:.1f}, size CV {:.3f}, spacing CV {:.3f}\n",
               seeds.size(), solvers[s], totals[s].spots, totals[s].size_cv, totals[s].spacing_cv);
  if (solvers.size() == 2)
    fmt::print("ratio {} / {}: solve {:.1f}x, total {:.1f}x\n", solvers[0], solvers[1],
               totals[0].solve / totals[1].solve, totals[0].total / totals[1].total);
  return 0;
}
