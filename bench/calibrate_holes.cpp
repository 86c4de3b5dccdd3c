// Measures the pattern's length scales for the hole map of docs/printing.md: runs the fast solver with
// epsilon = c h, alpha = kappa / epsilon^2 and dt = K epsilon^2 on a curved surface (a sphere) or a flat
// one (a square sheet), and prints, per pore level, the hole count, the nearest-neighbour spacing over
// epsilon, the hole diameter over that spacing (with CVs) and the porosity. Sheet holes within one spacing
// of the edge are left out of the statistics (cut by the edge).
// Usage: bench_calibrate --surface sphere|sheet --kappa 0.076 --phi-bar -0.33 --seeds 1,2,3

#include <fmt/core.h>

#include <CLI/CLI.hpp>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "band/band.hpp"
#include "geometry/mesh_surface.hpp"
#include "pattern/pattern.hpp"
#include "solver/fast_solver.hpp"
#include "solver/initial_condition.hpp"
#include "solver/time_stepping.hpp"

int main(int argc, char** argv) {
  using namespace poreshell;
  std::string surface_name = "sphere";
  int resolution = 131;
  double kappa = 0.076, phi_bar = -0.33, epsilon_per_h = 0.961, dt_per_eps2 = 14085.0;
  std::vector<std::uint64_t> seeds{1};
  std::vector<double> levels{-0.5, -0.4, -0.3, -0.2, -0.1, 0.0, 0.1, 0.2, 0.3, 0.4, 0.5};
  CLI::App app{"poreshell hole-map calibration"};
  app.add_option("--surface", surface_name);
  app.add_option("--resolution", resolution);
  app.add_option("--kappa", kappa);
  app.add_option("--phi-bar", phi_bar);
  app.add_option("--eps-per-h", epsilon_per_h);
  app.add_option("--dt-per-eps2", dt_per_eps2);
  app.add_option("--seeds", seeds)->delimiter(',');
  app.add_option("--levels", levels)->delimiter(',');
  CLI11_PARSE(app, argc, argv);

  std::unique_ptr<Surface> surface;
  std::function<bool(const Vec3&)> counted;
  constexpr double half = 0.4;  // sheet: the square [0.1, 0.9]^2 at z = 0.5
  if (surface_name == "sphere") {
    surface = std::make_unique<Sphere>(Vec3::Constant(0.5), 0.35);
  } else {
    TriangleMesh sheet;
    sheet.vertices = {{0.5 - half, 0.5 - half, 0.5},
                      {0.5 + half, 0.5 - half, 0.5},
                      {0.5 + half, 0.5 + half, 0.5},
                      {0.5 - half, 0.5 + half, 0.5}};
    sheet.triangles = {{0, 1, 2}, {0, 2, 3}};
    surface = std::make_unique<MeshSurface>(sheet);
  }
  const Grid grid = Grid::fitted(Box{Vec3::Zero(), Vec3::Ones()}, resolution);
  const NarrowBand band = build_band(*surface, grid);
  const double eps = epsilon_per_h * grid.h();
  const ModelParameters model{kappa / (eps * eps), eps, phi_bar};
  fmt::print("{} N={} band {} kappa {} phi_bar {} eps/h {} alpha {:.1f}\n", surface_name, resolution,
             band.size(), kappa, phi_bar, epsilon_per_h, model.alpha);
  for (std::uint64_t seed : seeds) {
    FastSolver solver(band, model, dt_per_eps2 * eps * eps);
    std::vector<double> phi = random_initial_condition(band, phi_bar, 0.5, seed);
    RunOptions options;
    options.min_spread = uniform_state_unstable(model.alpha, eps, phi_bar) ? 1.0 : 0.0;
    const RunResult run = run_to_steady_state(solver, phi, nullptr, options);
    // Sheet: holes whose centroid is more than one spacing (at level 0) inside the edge.
    const double spacing = hole_statistics(band, phi, 0.0).spacing_mean;
    if (surface_name != "sphere")
      counted = [spacing](const Vec3& c) {
        return std::abs(c.x() - 0.5) < half - spacing && std::abs(c.y() - 0.5) < half - spacing;
      };
    for (double level : levels) {
      const HoleStats s = hole_statistics(band, phi, level, counted);
      fmt::print(
          "seed {} steps {} level {:+.2f}: holes {} (all {}), a/eps {:.3f} (cv {:.3f}), D/a {:.3f} (cv "
          "{:.3f}), "
          "porosity {:.3f}\n",
          seed, run.steps, level, s.holes.size(), spot_statistics(band, phi, level).count,
          s.spacing_mean / eps, s.spacing_cv, s.diameter_mean / s.spacing_mean, s.diameter_cv, s.porosity);
    }
    std::fflush(stdout);
  }
}
