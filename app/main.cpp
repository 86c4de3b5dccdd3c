// poreshell: the command-line front end. Thin on purpose: flags -> PipelineConfig -> run_pipeline ->
// summary and report. All numerics and validation live in the library.

#include <fmt/core.h>
#include <fmt/format.h>
#include <tbb/global_control.h>

#include <CLI/CLI.hpp>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "io/atomic_file.hpp"
#include "pipeline/pipeline.hpp"
#include "pipeline/report.hpp"
#include "summary.hpp"

namespace {

namespace fs = std::filesystem;

constexpr int kExitFailure = 1;
constexpr int kExitUsage = 2;

// Fail before the (possibly minutes long) solve rather than after it, and never leave partial output.
void check_writable_location(const fs::path& path, const char* option) {
  const fs::path dir = path.parent_path().empty() ? fs::path(".") : path.parent_path();
  std::error_code ec;
  if (!fs::is_directory(dir, ec))
    throw poreshell::InputError(
        fmt::format("cannot write {} '{}': the directory '{}' does not exist; create it "
                    "or choose another path",
                    option, path.string(), dir.string()));
  if (fs::is_directory(path, ec))
    throw poreshell::InputError(
        fmt::format("cannot write {} '{}': it is a directory; give a file name", option, path.string()));
}

// Like CLI::PositiveNumber / NonNegativeNumber, but with a message that states the rule instead of
// printing the range up to DBL_MAX.
CLI::Validator number_above(double low, bool inclusive) {
  const std::string rule = inclusive ? ">= " : "> ";
  return CLI::Validator(
      [=](std::string& text) -> std::string {
        double v = 0.0;
        if (!CLI::detail::lexical_cast(text, v) || !std::isfinite(v) || (inclusive ? v < low : v <= low))
          return fmt::format("must be a number {}{:g}, got '{}'", rule, low, text);
        return {};
      },
      "", "");
}

int run(int argc, char** argv) {
  poreshell::PipelineConfig config;  // its defaults are the paper's section 3.2 values
  std::string output, report, inner = poreshell::to_string(config.inner.method);
  int threads = 0;
  bool quiet = false;

  CLI::App app{
      "poreshell: porous shells for 3D printing from the nonlocal Cahn-Hilliard equation on a narrow "
      "band (defaults: the sphere of section 3.2)",
      "poreshell"};
  app.set_version_flag("--version", std::string("poreshell ") + PORESHELL_VERSION);
  app.get_formatter()->column_width(28);

  auto* shape = app.add_option("--shape", config.shape, "surface S: sphere (eq. 3.1) or torus (section 3.2)")
                    ->check(CLI::IsMember({"sphere", "torus"}))
                    ->capture_default_str();
  std::string mesh;
  auto* mesh_option =
      app.add_option(
             "--mesh", mesh,
             "triangle mesh FILE (STL, OBJ, PLY, OFF, 3MF; holes and open surfaces are fine), fitted to "
             "the unit grid as in section 3.4; coordinates in --units")
          ->type_name("FILE")
          ->excludes(shape);
  std::string points;
  app.add_option(
         "--points", points,
         "point cloud FILE (.xyz: x y z a line, extra columns ignored; .ply: its vertices), fitted to "
         "the unit grid like --mesh")
      ->type_name("FILE")
      ->excludes(shape)
      ->excludes(mesh_option);
  app.add_option("--point-route", config.point_route,
                 "point clouds: direct (distance to discs fitted to the points, no PDE) or paper (densify, "
                 "then the segmentation eq. 3.3; needs a closed surface); docs/point-clouds.md")
      ->check(CLI::IsMember({"direct", "paper"}))
      ->capture_default_str();
  app.add_option("--resolution", config.resolution,
                 "grid points N_x along the longest side, h = 1/(N_x - 1) (paper: 131, Fig. 5: 181)")
      ->type_name("N")
      ->check(number_above(0.0, false))
      ->capture_default_str();
  app.add_option("--voxel-size", config.voxel_size,
                 "grid spacing h in mm; sets the resolution instead of --resolution")
      ->type_name("MM")
      ->check(number_above(0.0, false));
  app.add_option(
         "--units", config.units,
         "unit of the input's coordinates (shapes: of the unit cube); lengths on the command line and "
         "all outputs are in mm")
      ->check(CLI::IsMember({"m", "cm", "mm", "inch"}))
      ->capture_default_str();
  app.add_option("--mode", config.mode,
                 "shell: wall of --wall mm, pores straight through it; narrow-volume: the paper's Fig. 3b "
                 "(about 3.8 h thick)")
      ->check(CLI::IsMember({"shell", "narrow-volume"}))
      ->capture_default_str();
  app.add_option("--wall", config.wall,
                 "shell wall thickness in mm (default: the band's width 2 delta = 3.81 h)")
      ->type_name("MM")
      ->check(number_above(0.0, false));
  app.add_option("--offset", config.offset,
                 "where the shell wall lies: centered on the surface, inside or outside it")
      ->check(CLI::IsMember({"centered", "inside", "outside"}))
      ->capture_default_str();
  app.add_option("--alpha", config.alpha,
                 "nonlocal strength α in eq. (2.1) (paper: 1400 sphere and torus, 2200 bunny)")
      ->type_name("A")
      ->check(number_above(0.0, true))
      ->capture_default_str();
  app.add_option("--epsilon-m", config.epsilon_m,
                 "interface width m in ε_m = m h / (2√2 tanh⁻¹ 0.9) (paper: 4)")
      ->type_name("M")
      ->check(number_above(0.0, false))
      ->capture_default_str();
  app.add_option("--dt-h", config.dt_in_h, "time step Δt in units of h, Δt = K h (paper: 100)")
      ->type_name("K")
      ->check(number_above(0.0, false))
      ->capture_default_str();
  app.add_option("--tol", config.tolerance, "stop when the consecutive change e_c < tol (paper: 1e-3)")
      ->type_name("T")
      ->check(number_above(0.0, false))
      ->capture_default_str();
  app.add_option("--max-steps", config.max_steps,
                 "at most S time steps (paper: T = 329 Δt sphere, 358 Δt torus)")
      ->type_name("S")
      ->check(number_above(0.0, false))
      ->capture_default_str();
  app.add_option("--seed", config.seed, "seed of rand(x) in φ(x, 0) = φ̄ + 0.5 rand(x)")
      ->type_name("S")
      ->capture_default_str();
  app.add_option(
         "--iso", config.iso_levels,
         "isosurface level(s) φ = C of the narrow volume, comma-separated or repeated (paper: 0.3, 0, -0.3)")
      ->type_name("C[,C...]")
      ->delimiter(',')
      ->allow_extra_args(false)  // one token per --iso, so "--iso 0.3 OUT" cannot swallow a stray word
      ->capture_default_str();
  app.add_option("--energy-every", config.energy_every,
                 "evaluate the discrete energy (3.2) every K steps and at the end; 0 = never (saves its "
                 "Poisson factorisation on large grids)")
      ->type_name("K")
      ->check(number_above(0.0, true))
      ->capture_default_str();
  app.add_option("--threads", threads, "worker threads (oneTBB); 0 = all cores")
      ->type_name("N")
      ->check(number_above(0.0, true))
      ->capture_default_str();
  app.add_option("--phi-bar", config.phi_bar,
                 "mean concentration φ̄ in eq. (2.1), sets the pore fraction (paper: -0.3)")
      ->type_name("F")
      ->capture_default_str();
  auto* alpha_option = app.get_option("--alpha");
  const std::vector<CLI::Option*> model_options{alpha_option, app.get_option("--epsilon-m"),
                                                app.get_option("--dt-h"), app.get_option("--phi-bar"),
                                                app.get_option("--iso")};
  std::vector<CLI::Option*> hole_options{
      app.add_option(
             "--hole-diameter", config.holes.diameter,
             "hole diameter in mm; sets alpha, epsilon, phi-bar, the time step, the pore level and the "
             "voxel size (docs/printing.md)")
          ->type_name("MM")
          ->check(number_above(0.0, false)),
      app.add_option("--spacing", config.holes.spacing,
                     "hole centre spacing in mm (default with --hole-diameter: diameter / 0.6)")
          ->type_name("MM")
          ->check(number_above(0.0, false)),
      app.add_option("--porosity", config.holes.porosity, "open share of the surface, instead of --spacing")
          ->type_name("F")
          ->check(number_above(0.0, false))};
  for (CLI::Option* hole : hole_options)
    for (CLI::Option* model : model_options) hole->excludes(model);
  std::string grade;
  app.add_option("--grade", grade,
                 "hole-size grading, diameters in mm: axis:x|y|z:D1:D2, line:X,Y,Z:D1:X,Y,Z:D2, "
                 "radial:X,Y,Z:R:D0 or field:NAME[:D0:D1] (a PLY vertex property)")
      ->type_name("SPEC");
  app.add_option("--radius", config.shape_radius,
                 "size of --shape in mm: sphere radius, torus major radius (default: the unit cube)")
      ->type_name("MM")
      ->check(number_above(0.0, false))
      ->excludes(mesh_option);
  app.add_option("--rim", config.rim_mm, "solid rim of this width (mm) along the mesh's open boundary")
      ->type_name("MM")
      ->check(number_above(0.0, true));
  std::vector<std::string> keep_out;
  app.add_option("--keep-out", keep_out,
                 "solid sphere X,Y,Z,R in mm (input frame) where no pore may form; repeatable")
      ->type_name("X,Y,Z,R");
  app.add_option("--max-triangles", config.max_triangles,
                 "reduce each output to at most N triangles, keeping it closed, manifold and within "
                 "--max-deviation of the meshed surface")
      ->type_name("N")
      ->check(number_above(0.0, true));
  app.add_option("--max-deviation", config.max_deviation,
                 "how far (mm) the reduced surface may lie from the meshed one; keep it below half the wall")
      ->type_name("MM")
      ->check(number_above(0.0, false))
      ->capture_default_str();
  app.add_option("--keep-out-mask", config.keep_out_mask,
                 "solid wherever this vertex property of the --mesh PLY file is 1 (a painted 0/1 mask)")
      ->type_name("NAME");
  std::vector<std::string> keep_out_boxes;
  app.add_option("--keep-out-box", keep_out_boxes,
                 "solid box X0,Y0,Z0,X1,Y1,Z1 in mm (input frame, two opposite corners); repeatable")
      ->type_name("X0,Y0,Z0,X1,Y1,Z1");
  app.add_option("--max-memory", config.max_memory_gb,
                 "refuse runs estimated to need more memory than this, in GB (default: what is available)")
      ->type_name("GB")
      ->check(number_above(0.0, false));
  app.add_option("--solver", config.solver,
                 "fast: stabilised scheme, band multigrid (docs/solver.md); reference: the paper's scheme")
      ->check(CLI::IsMember({"fast", "reference"}))
      ->capture_default_str();
  app.add_option("--fast-tol", config.fast.tolerance, "fast solver: bound on the error of each step's solve")
      ->type_name("T")
      ->check(number_above(0.0, false))
      ->capture_default_str();
  app.add_option("--min-stabilisation", config.fast.min_stabilisation,
                 "fast solver: floor on the stabilisation S (default: the energy-stability bound alone)")
      ->type_name("S")
      ->check(number_above(0.0, true))
      ->capture_default_str();
  std::string coarse_start = "auto";
  app.add_option(
         "--coarse-start", coarse_start,
         "fast solver: auto forms the pattern on a coarser grid first where epsilon spans 1.8 eps_4 "
         "or more (fine voxels for large pores), then relaxes it here; off solves here from the start")
      ->check(CLI::IsMember({"auto", "off"}))
      ->capture_default_str();
  app.add_option("--inner", inner, "reference solver: inner relaxation per step (paper: jacobi)")
      ->check(CLI::IsMember({"gauss-seidel", "jacobi"}))
      ->capture_default_str();
  app.add_option("--inner-tol", config.inner.tolerance,
                 "inner tolerance on the max-norm scaled residual of eqs. (2.3)-(2.4)")
      ->type_name("T")
      ->check(number_above(0.0, false))
      ->capture_default_str();
  // Required, but checked after parsing: CLI11 reports a missing required option before an unknown one,
  // which would hide a misspelt flag behind "--output is required".
  app.add_option("-o,--output", output,
                 "output mesh in mm (required); the extension picks the format: .stl (binary), .3mf, .obj, "
                 ".ply (binary); several --iso levels write OUT-isoC.ext each")
      ->type_name("OUT.stl");
  app.add_option("--report", report, "write the run's JSON report here")->type_name("OUT.json");
  app.add_flag("-q,--quiet", quiet, "no per-step progress on stderr");

  app.allow_extras();

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e);  // --help, --version
    fmt::print(stderr, "poreshell: error: {} (see poreshell --help)\n", e.what());
    return kExitUsage;
  }
  if (!app.remaining().empty()) {
    fmt::print(stderr, "poreshell: error: unknown argument '{}' (see poreshell --help)\n",
               app.remaining().front());
    return kExitUsage;
  }
  if (output.empty()) {
    fmt::print(stderr, "poreshell: error: no output file: give -o OUT.stl (see poreshell --help)\n");
    return kExitUsage;
  }

  config.inner.method = poreshell::parse_inner_iteration(inner);
  config.coarse_start = coarse_start == "auto";
  config.output = output;
  for (const std::string& text : keep_out) {
    std::array<double, 4> sphere{};
    char extra = 0;
    if (std::sscanf(text.c_str(), "%lf,%lf,%lf,%lf%c", &sphere[0], &sphere[1], &sphere[2], &sphere[3],
                    &extra) != 4) {
      fmt::print(
          stderr,
          "poreshell: error: --keep-out '{}' is not X,Y,Z,R (four numbers, mm) (see poreshell --help)\n",
          text);
      return kExitUsage;
    }
    config.keep_out.push_back(sphere);
  }
  for (const std::string& text : keep_out_boxes) {
    std::array<double, 6> box{};
    char extra = 0;
    if (std::sscanf(text.c_str(), "%lf,%lf,%lf,%lf,%lf,%lf%c", &box[0], &box[1], &box[2], &box[3], &box[4],
                    &box[5], &extra) != 6) {
      fmt::print(stderr,
                 "poreshell: error: --keep-out-box '{}' is not X0,Y0,Z0,X1,Y1,Z1 (six numbers, mm) (see "
                 "poreshell --help)\n",
                 text);
      return kExitUsage;
    }
    config.keep_out_boxes.push_back(box);
  }
  config.mesh = mesh;
  config.points = points;
  if (!grade.empty()) config.grade = poreshell::parse_grade(grade);
  check_writable_location(config.output, "the output");
  if (!report.empty()) check_writable_location(report, "the report");

  // Held for the whole run: oneTBB honours the limit only while the object lives.
  std::optional<tbb::global_control> thread_limit;
  if (threads > 0)
    thread_limit.emplace(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));

  const auto start = std::chrono::steady_clock::now();
  if (!quiet) config.on_step = [start](const poreshell::StepProgress& p) { print_progress(p, start); };

  const poreshell::PipelineResult result = poreshell::run_pipeline(config);

  if (!report.empty())
    poreshell::write_atomically(
        report, [&](std::ostream& out) { out << poreshell::to_json(result).dump(2) << '\n'; }, false);

  print_summary(config, result, report);
  if (!result.run.reached_tolerance)
    fmt::print(
        stderr,
        "poreshell: warning: stopped at --max-steps {} with e_c = {:.3e} above --tol {:g}; the pattern may "
        "not be steady yet, raise --max-steps\n",
        result.run.steps, result.run.final_ec, config.tolerance);
  if (!result.run.inner_converged)
    fmt::print(
        stderr,
        "poreshell: warning: some steps did not reach --inner-tol {:g}; the result may be inaccurate\n",
        config.inner.tolerance);
  if (result.grading && result.grading->clamped_fraction > 0.0)
    fmt::print(
        stderr,
        "poreshell: warning: the grading asked for holes from {:.3g} to {:.3g} mm; at {:.3g} mm spacing "
        "they were clamped to {:.3g}-{:.3g} mm on {:.1f}% of the surface (wider holes would merge, "
        "narrower ones close)\n",
        result.grading->min_diameter, result.grading->max_diameter, result.plan->spacing,
        result.grading->clamped_min, result.grading->clamped_max, 100.0 * result.grading->clamped_fraction);
  const poreshell::ModelParameters& m = result.model;
  if (!poreshell::uniform_state_unstable(m.alpha, m.epsilon, m.phi_bar)) {
    const double a = 1.0 - 3.0 * m.phi_bar * m.phi_bar;
    fmt::print(stderr,
               "poreshell: warning: no pattern can form: the uniform state is stable for alpha {:g}, epsilon "
               "{:.4g}, phi-bar {:g} (needs 4 alpha eps^2 < (1 - 3 phi_bar^2)^2); use --alpha below {:.4g}\n",
               m.alpha, m.epsilon, m.phi_bar, a > 0 ? a * a / (4 * m.epsilon * m.epsilon) : 0.0);
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return run(argc, argv);
  } catch (const std::exception& e) {  // poreshell::InputError included: its message says what to fix
    fmt::print(stderr, "poreshell: error: {}\n", e.what());
  } catch (...) {
    fmt::print(stderr, "poreshell: error: unknown failure\n");
  }
  return kExitFailure;
}
