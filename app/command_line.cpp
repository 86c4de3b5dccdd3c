// The command line's option table: argv -> Command (poreshell::Options and the files). Parsing only;
// main.cpp runs it.

#include "command_line.hpp"

#include <algorithm>
#include <map>

#include "cli_support.hpp"

namespace {

const std::map<std::string, poreshell::Unit> kUnits{{"m", poreshell::Unit::m},
                                                    {"cm", poreshell::Unit::cm},
                                                    {"mm", poreshell::Unit::mm},
                                                    {"inch", poreshell::Unit::inch}};
// The library's names of an option's values, with - for _ as flags are spelled.
template <class Enum>
std::map<std::string, Enum> flag_names() {
  std::map<std::string, Enum> names;
  for (const auto& [name, value] : poreshell::enum_names(Enum{})) {
    std::string flag(name);
    std::replace(flag.begin(), flag.end(), '_', '-');
    names.emplace(std::move(flag), value);
  }
  return names;
}
const auto kModes = flag_names<poreshell::Mode>();
const auto kOffsets = flag_names<poreshell::WallOffset>();
const auto kSolvers = flag_names<poreshell::SolverKind>();
const auto kInners = flag_names<poreshell::InnerIteration>();
const auto kPointRoutes = flag_names<poreshell::PointRoute>();
const auto kStopRules = flag_names<poreshell::StopRule>();
const auto kLayouts = flag_names<poreshell::Layout>();

// Like CLI::CheckedTransformer, with a message that lists the names alone: "--units: 'furlong' is not
// one of cm, inch, m, mm".
template <class Enum>
CLI::Validator one_of(const std::map<std::string, Enum>& names) {
  std::string list;
  for (const auto& entry : names) list += (list.empty() ? "" : ", ") + entry.first;
  return CLI::Validator(
      [&names, list](std::string& text) -> std::string {
        const auto it = names.find(text);
        if (it == names.end()) return "'" + text + "' is not one of " + list;
        text = std::to_string(static_cast<int>(it->second));
        return {};
      },
      "", "");
}

// --preview and --stop (docs/solver.md "Stop rules").
void add_stop_flags(CLI::App& app, poreshell::Options& options) {
  app.add_flag("--preview", options.preview,
               "the pattern alone, fast: the surface with its holes painted on (.ply with vertex colours, "
               "--html), no shell; with --layout cvt the full run's starting discs, else the equation "
               "stopped as soon as the hole layout has settled");
  app.add_option(
         "--stop", options.stop,
         "when the run ends: holes (the hole count, centres and boundaries have settled; the default "
         "with --layout cvt and for --preview) or paper (e_c < --tol; the default with --layout paper)")
      ->transform(one_of(kStopRules))
      ->default_str("auto");
  app.add_option("--layout", options.layout,
                 "the hole layout: cvt (the equation started from discs at a centroidal Voronoi "
                 "tessellation of the free surface at its own hole density; the default with "
                 "--hole-diameter, which it needs) or paper (the pattern forming from noise; the default "
                 "with the paper's parameters)")
      ->transform(one_of(kLayouts))
      ->default_str("auto");
}

}  // namespace

std::optional<Command> parse_command_line(int argc, const char* const* argv) {
  Command command;
  command.arguments.assign(argv, argv + argc);
  poreshell::Options& options = command.options;  // its defaults are the paper's section 3.2 values
  std::string &output = command.output, &report = command.report, &holes_csv = command.holes_csv,
              &html = command.html, &png = command.png, &shape_name = command.shape_name,
              &mesh = command.mesh, &points = command.points, &progress = command.progress;
  poreshell::Unit& unit = command.unit;
  double& radius = command.radius;
  bool& quiet = command.quiet;

  CLI::App app{
      "poreshell: porous shells for 3D printing from the nonlocal Cahn-Hilliard equation on a narrow "
      "band (defaults: the sphere of section 3.2)",
      "poreshell"};
  app.set_version_flag("--version", std::string("poreshell ") + poreshell::version());
  app.get_formatter()->column_width(28);

  auto* shape = app.add_option("--shape", shape_name, "surface S: sphere (eq. 3.1) or torus (section 3.2)")
                    ->check(CLI::IsMember({"sphere", "torus"}))
                    ->capture_default_str();
  auto* mesh_option =
      app.add_option(
             "--mesh", mesh,
             "triangle mesh FILE (STL, OBJ, PLY, OFF, 3MF; holes and open surfaces are fine), fitted to "
             "the unit grid as in section 3.4; coordinates in --units")
          ->type_name("FILE")
          ->excludes(shape);
  app.add_option(
         "--points", points,
         "point cloud FILE (.xyz: x y z a line, extra columns ignored; .ply: its vertices), fitted to "
         "the unit grid like --mesh")
      ->type_name("FILE")
      ->excludes(shape)
      ->excludes(mesh_option);
  app.add_option("--point-route", options.point_route,
                 "point clouds: direct (distance to discs fitted to the points, no PDE) or paper (densify, "
                 "then the segmentation eq. 3.3; needs a closed surface); docs/point-clouds.md")
      ->transform(one_of(kPointRoutes))
      ->default_str("direct");
  app.add_option("--resolution", options.resolution,
                 "grid points N_x along the longest side, h = 1/(N_x - 1) (paper: 131, Fig. 5: 181)")
      ->type_name("N")
      ->check(number_above(0.0, false))
      ->capture_default_str();
  app.add_option("--voxel-size", options.voxel_size,
                 "grid spacing h in mm; sets the resolution instead of --resolution")
      ->type_name("MM")
      ->check(number_above(0.0, false));
  app.add_option(
         "--units", unit,
         "unit of the input's coordinates (shapes: of the unit cube); lengths on the command line and "
         "all outputs are in mm")
      ->transform(one_of(kUnits))
      ->default_str("mm");
  app.add_option("--mode", options.mode,
                 "shell: wall of --wall mm, pores straight through it; narrow-volume: the paper's Fig. 3b "
                 "(about 3.8 h thick)")
      ->transform(one_of(kModes))
      ->default_str("shell");
  app.add_option(
         "--wall", options.wall,
         "shell wall thickness in mm (default: 2 mm with holes in mm; with the paper's parameters the band's "
         "width 2 delta = 3.81 h)")
      ->type_name("MM")
      ->check(number_above(0.0, false));
  app.add_option("--offset", options.offset,
                 "where the shell wall lies: centered on the surface, inside or outside it")
      ->transform(one_of(kOffsets))
      ->default_str("centered");
  app.add_option("--alpha", options.alpha,
                 "nonlocal strength α in eq. (2.1) (paper: 1400 sphere and torus, 2200 bunny)")
      ->type_name("A")
      ->check(number_above(0.0, true))
      ->capture_default_str();
  app.add_option("--epsilon-m", options.epsilon_m,
                 "interface width m in ε_m = m h / (2√2 tanh⁻¹ 0.9) (paper: 4)")
      ->type_name("M")
      ->check(number_above(0.0, false))
      ->capture_default_str();
  app.add_option("--dt-h", options.dt_h, "time step Δt in units of h, Δt = K h (paper: 100)")
      ->type_name("K")
      ->check(number_above(0.0, false))
      ->capture_default_str();
  add_stop_flags(app, options);
  app.add_option("--tol", options.tolerance, "stop when the consecutive change e_c < tol (paper: 1e-3)")
      ->type_name("T")
      ->check(number_above(0.0, false))
      ->capture_default_str();
  app.add_option("--max-steps", options.max_steps,
                 "at most S time steps (paper: T = 329 Δt sphere, 358 Δt torus)")
      ->type_name("S")
      ->check(number_above(0.0, false))
      ->capture_default_str();
  app.add_option("--seed", options.seed, "seed of rand(x) in φ(x, 0) = φ̄ + 0.5 rand(x)")
      ->type_name("S")
      ->check(number_above(0.0, true))
      ->capture_default_str();
  app.add_option(
         "--iso", options.iso,
         "isosurface level(s) φ = C of the narrow volume, comma-separated or repeated (paper: 0.3, 0, -0.3)")
      ->type_name("C[,C...]")
      ->delimiter(',')
      ->allow_extra_args(false)  // one token per --iso, so "--iso 0.3 OUT" cannot swallow a stray word
      ->capture_default_str();
  app.add_option("--energy-every", options.energy_every,
                 "evaluate the discrete energy (3.2) every K steps and at the end; 0 = never (saves its "
                 "Poisson factorisation on large grids)")
      ->type_name("K")
      ->check(number_above(0.0, true))
      ->capture_default_str();
  app.add_option("--threads", options.threads, "worker threads (oneTBB); 0 = all cores")
      ->type_name("N")
      ->check(number_above(0.0, true))
      ->capture_default_str();
  app.add_option("--phi-bar", options.phi_bar,
                 "mean concentration φ̄ in eq. (2.1), sets the pore fraction (paper: -0.3)")
      ->type_name("F")
      ->capture_default_str();
  auto* alpha_option = app.get_option("--alpha");
  const std::vector<CLI::Option*> model_options{alpha_option, app.get_option("--epsilon-m"),
                                                app.get_option("--dt-h"), app.get_option("--phi-bar"),
                                                app.get_option("--iso")};
  std::vector<CLI::Option*> hole_options{
      app.add_option(
             "--hole-diameter", options.hole_diameter,
             "hole diameter in mm; sets alpha, epsilon, phi-bar, the time step, the pore level and the "
             "voxel size (docs/printing.md)")
          ->type_name("MM")
          ->check(number_above(0.0, false)),
      app.add_option("--spacing", options.spacing,
                     "hole centre spacing in mm (default with --hole-diameter: diameter / 0.6)")
          ->type_name("MM")
          ->check(number_above(0.0, false)),
      app.add_option("--porosity", options.porosity, "open share of the surface, instead of --spacing")
          ->type_name("F")
          ->check(number_above(0.0, false))};
  for (CLI::Option* hole : hole_options)
    for (CLI::Option* model : model_options) hole->excludes(model);
  std::string grade;
  app.add_option("--grade", grade,
                 "hole-size grading, diameters in mm: axis:x|y|z:D1:D2, line:X,Y,Z:D1:X,Y,Z:D2, "
                 "radial:X,Y,Z:R:D0 or field:NAME[:D0:D1] (a PLY vertex property)")
      ->type_name("SPEC");
  app.add_option("--radius", radius,
                 "size of --shape in mm: sphere radius, torus major radius (default: the unit cube)")
      ->type_name("MM")
      ->check(number_above(0.0, false))
      ->excludes(mesh_option);
  app.add_option(
         "--rim", options.rim,
         "solid rim of this width (mm) along the mesh's open boundary (default: half a hole with holes in "
         "mm, so that none is cut open; 0: none)")
      ->type_name("MM")
      ->check(number_above(0.0, true));
  std::vector<std::string> keep_out;
  app.add_option("--keep-out", keep_out,
                 "solid sphere X,Y,Z,R in mm (input frame) where no pore may form; repeatable")
      ->type_name("X,Y,Z,R");
  app.add_option("--max-triangles", options.max_triangles,
                 "reduce each output to at most N triangles, keeping it closed, manifold and within "
                 "--max-deviation of the full isosurface; fails naming the fewest that keep the bound")
      ->type_name("N")
      ->check(number_above(0.0, true));
  app.add_option("--max-deviation", options.max_deviation,
                 "the written surface lies within this distance (mm, both ways, checked) of the full "
                 "isosurface, with fewer triangles where the shape allows; 0: the full isosurface")
      ->type_name("MM")
      ->check(number_above(0.0, true))
      ->capture_default_str();
  app.add_option("--keep-out-mask", options.keep_out_mask,
                 "solid wherever this vertex property of the --mesh PLY file is 1 (a painted 0/1 mask)")
      ->type_name("NAME");
  std::vector<std::string> keep_out_boxes;
  app.add_option("--keep-out-box", keep_out_boxes,
                 "solid box X0,Y0,Z0,X1,Y1,Z1 in mm (input frame, two opposite corners); repeatable")
      ->type_name("X0,Y0,Z0,X1,Y1,Z1");
  app.add_option("--max-seconds", command.max_seconds,
                 "stop a run still computing after this many seconds, with a message and no file")
      ->type_name("S")
      ->check(number_above(0.0, false));
  app.add_option("--max-memory", options.max_memory_gb,
                 "refuse runs estimated to need more memory than this, in GB (default: what is available)")
      ->type_name("GB")
      ->check(number_above(0.0, false));
  app.add_option("--solver", options.solver,
                 "fast: stabilised scheme, band multigrid (docs/solver.md); reference: the paper's scheme")
      ->transform(one_of(kSolvers))
      ->default_str("fast");
  app.add_option("--fast-tol", options.fast_tolerance, "fast solver: bound on the error of each step's solve")
      ->type_name("T")
      ->check(number_above(0.0, false))
      ->capture_default_str();
  app.add_option("--min-stabilisation", options.min_stabilisation,
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
  app.add_option("--inner", options.inner, "reference solver: inner relaxation per step (paper: jacobi)")
      ->transform(one_of(kInners))
      ->default_str("gauss-seidel");
  app.add_option("--inner-tol", options.inner_tolerance,
                 "inner tolerance on the max-norm scaled residual of eqs. (2.3)-(2.4)")
      ->type_name("T")
      ->check(number_above(0.0, false))
      ->capture_default_str();
  // This or a view is required, checked after parsing: CLI11 reports a missing required option before an
  // unknown one, which would hide a misspelt flag behind "--output is required".
  app.add_option(
         "-o,--output", output,
         "output mesh in mm; the extension picks the format: .stl (binary), .3mf, .obj, .ply (binary); "
         "several --iso levels write OUT-isoC.ext each. Without it, only --html, --png, --holes or "
         "--report are written (to look before printing)")
      ->type_name("OUT.stl");
  app.add_option("--report", report, "write the run's JSON report here")->type_name("OUT.json");
  app.add_flag("-q,--quiet", quiet, "nothing on stdout and no progress: only errors and warnings, on stderr");
  app.add_option("--progress", progress,
                 "progress on stderr: auto (a bar per stage with the time left on a terminal, else plain "
                 "lines), bar, plain, or json (one object a line: stage, fraction, seconds, eta)")
      ->check(CLI::IsMember({"auto", "bar", "plain", "json"}))
      ->capture_default_str();
  app.add_option("--scale", options.scale,
                 "multiply the input's coordinates by F (after --units); lengths on the command line are "
                 "in mm of the scaled model")
      ->type_name("F")
      ->check(number_above(0.0, false));
  app.add_option("--thin-features", options.thin_feature_ratio,
                 "no hole where the part is thinner than this many hole diameters (ears, fingers); 0: off")
      ->type_name("RATIO")
      ->check(number_above(0.0, true))
      ->capture_default_str();
  app.add_option("--crease-angle", options.crease_angle,
                 "no hole within half a hole of an edge sharper than this (degrees); 0: off")
      ->type_name("DEG")
      ->check(number_above(0.0, true))
      ->capture_default_str();
  app.add_flag("--keep-fragments", options.keep_fragments,
               "keep specks and sealed voids under 1% of the largest part's volume (removed by default)");

  app.add_option("--holes", holes_csv,
                 "write the hole table (centre, normal, diameter, circularity, nearest, axis ratio) as CSV")
      ->type_name("OUT.csv");
  app.add_option("--html", html, "write the interactive viewer: one self-contained page, opens offline")
      ->type_name("OUT.html");
  app.add_option("--png", png, "write a picture of the viewer's view (needs chromium)")->type_name("OUT.png");
  app.add_option("--project", command.project,
                 "run a studio project (docs/studio.md): its model, settings, keep-outs and painted mask; "
                 "the same file as the studio's Make")
      ->type_name("FILE")
      ->excludes(shape)
      ->excludes(mesh_option);
  app.footer("poreshell studio [MODEL] [--port N] ...: the browser front end (poreshell studio --help)");
  app.allow_extras();

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) {  // --help, --version
      app.exit(e);
      return std::nullopt;
    }
    std::string message = e.what();
    // CLI11's "--wall: At Most 1 required but received 2" for a repeated option.
    if (const auto at = message.find(": At Most 1 required but received"); at != std::string::npos)
      message = message.substr(0, at) + " given more than once; give it once";
    throw UsageError(message);
  }
  if (!app.remaining().empty()) throw UsageError(unknown_argument_message(app, app.remaining().front()));
  if (output.empty() && html.empty() && png.empty() && holes_csv.empty() && report.empty())
    throw UsageError(
        "no output file: give -o OUT.stl for the part, or --html OUT.html to look at it first (or --png, "
        "--holes, --report)");
  options.coarse_start = coarse_start == "auto";
  for (const std::string& text : keep_out) {
    const auto v = numbers(text, 4);
    if (!v) throw UsageError("--keep-out '" + text + "' is not X,Y,Z,R (four numbers, mm)");
    options.keep_out.push_back({{(*v)[0], (*v)[1], (*v)[2]}, (*v)[3]});
  }
  for (const std::string& text : keep_out_boxes) {
    const auto v = numbers(text, 6);
    if (!v) throw UsageError("--keep-out-box '" + text + "' is not X0,Y0,Z0,X1,Y1,Z1 (six numbers, mm)");
    options.keep_out_boxes.push_back({{(*v)[0], (*v)[1], (*v)[2]}, {(*v)[3], (*v)[4], (*v)[5]}});
  }
  if (!grade.empty()) options.grade = poreshell::parse_grade(grade);
  poreshell::validate(options);
  return command;
}
