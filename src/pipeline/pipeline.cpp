#include "pipeline/pipeline.hpp"

#include <tbb/global_control.h>

#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <sstream>

#include "core/error.hpp"
#include "core/heap.hpp"
#include "core/units.hpp"
#include "geometry/isosurface.hpp"
#include "geometry/mesh_surface.hpp"
#include "geometry/winding_number.hpp"
#include "input/placement.hpp"
#include "input/point_cloud.hpp"
#include "input/point_segmentation.hpp"
#include "input/vertex_field.hpp"
#include "io/file_format.hpp"
#include "io/mesh_io.hpp"
#include "io/mesh_writers.hpp"
#include "io/point_io.hpp"
#include "pattern/solid_zones.hpp"
#include "shell/shell.hpp"
#include "solver/coarse_start.hpp"
#include "solver/initial_condition.hpp"

namespace poreshell {
namespace {

// The process's peak resident set so far (Linux reports kilobytes).
std::size_t peak_rss_bytes() {
  rusage usage{};
  if (getrusage(RUSAGE_SELF, &usage) != 0) return 0;
  return static_cast<std::size_t>(usage.ru_maxrss) * 1024;
}

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

void validate(const PipelineConfig& c) {
  if (c.resolution < 9)
    throw InputError("--resolution must be at least 9 grid points along the longest side");
  if (c.resolution > 2048)
    throw InputError("--resolution above 2048 is not supported by the reference solver");
  if (c.voxel_size < 0.0 || !std::isfinite(c.voxel_size))
    throw InputError("--voxel-size must be a positive length in millimetres");
  millimetres_per_unit(c.units);  // throws for an unknown unit
  if (c.mode != "shell" && c.mode != "narrow-volume")
    throw InputError("unknown --mode '" + c.mode + "': use shell or narrow-volume");
  if (!(c.wall >= 0.0) || !std::isfinite(c.wall))
    throw InputError("--wall must be a positive thickness in millimetres (0: the default)");
  parse_wall_offset(c.offset);
  if (c.mode == "narrow-volume" && (c.wall > 0.0 || c.offset != "centered"))
    throw InputError("--wall and --offset shape the shell: use them with --mode shell");
  if (c.point_route != "direct" && c.point_route != "paper")
    throw InputError("unknown --point-route '" + c.point_route + "': use direct or paper");
  if (!c.points.empty() && !c.mesh.empty()) throw InputError("give either --mesh or --points, not both");
  if (!(c.max_memory_gb >= 0.0)) throw InputError("--max-memory must be a positive number of GB");
  if (!(c.rim_mm >= 0.0)) throw InputError("--rim must be a width >= 0 in mm");
  for (const auto& k : c.keep_out)
    if (!(k[3] > 0.0) || !std::isfinite(k[0] + k[1] + k[2] + k[3]))
      throw InputError("--keep-out takes X,Y,Z,R in mm with a radius R > 0");
  for (const auto& k : c.keep_out_boxes)
    if (!(k[3] > k[0] && k[4] > k[1] && k[5] > k[2]) ||
        !std::isfinite(k[0] + k[1] + k[2] + k[3] + k[4] + k[5]))
      throw InputError("--keep-out-box takes X0,Y0,Z0,X1,Y1,Z1 in mm with X0 < X1, Y0 < Y1 and Z0 < Z1");
  if ((c.rim_mm > 0.0 || !c.keep_out.empty() || !c.keep_out_boxes.empty() || !c.keep_out_mask.empty()) &&
      c.solver != "fast")
    throw InputError("--rim and --keep-out act through the fast solver: drop --solver reference");
  if (c.solver != "fast" && c.solver != "reference")
    throw InputError("unknown --solver '" + c.solver + "': use fast or reference");
  if (!(c.epsilon_m > 0.0)) throw InputError("--epsilon-m must be positive (the paper uses 4)");
  if (!(c.tolerance > 0.0)) throw InputError("--tol must be positive (the paper uses 1e-3)");
  if (c.max_steps < 1) throw InputError("--max-steps must be at least 1");
  if (c.energy_every < 0) throw InputError("--energy-every must be >= 0 (0 turns the energy off)");
  if (!(c.amplitude >= 0.0)) throw InputError("the initial amplitude must be >= 0");
  if (c.iso_levels.empty()) throw InputError("give at least one --iso level");
  for (std::size_t i = 0; i < c.iso_levels.size(); ++i) {
    if (!(c.iso_levels[i] > -1.0 && c.iso_levels[i] < 1.0))
      throw InputError("--iso levels must lie strictly between -1 and 1");
    for (std::size_t j = 0; j < i; ++j)
      if (c.iso_levels[j] == c.iso_levels[i]) throw InputError("--iso lists the same level twice");
  }
  // The model's own checks (epsilon is set from the grid later; any positive value passes here).
  poreshell::validate(ModelParameters{c.alpha, 1.0, c.phi_bar}, c.dt_in_h);
  if (!(c.shape_radius >= 0.0) || !std::isfinite(c.shape_radius))
    throw InputError("--radius must be a positive length in millimetres");
  if (c.shape_radius > 0.0 && (!c.mesh.empty() || !c.points.empty()))
    throw InputError("--radius sizes a --shape: a mesh or point cloud keeps its own size (see --units)");
  if (c.shape_radius > 0.0 && c.units != "mm")
    throw InputError("--units names the unit of an input file: a --shape with --radius is in mm already");
  if (c.grade && c.holes.empty())
    throw InputError(
        "--grade sets hole diameters in mm: add --hole-diameter MM (and --spacing MM or --porosity F)");
  if (c.max_triangles < 0 || (c.max_triangles > 0 && c.max_triangles < 4))
    throw InputError("--max-triangles must be at least 4 (0: keep every triangle)");
  if (!(c.max_deviation > 0.0) || !std::isfinite(c.max_deviation))
    throw InputError("--max-deviation must be a positive length in mm");
  if (c.output.empty()) throw InputError("give an output file with -o OUT.stl");
  check_output_extension(c.output);
}

// Which side of the surface a point lies on, where the wall's offset needs it: a mesh input's winding
// number (shapes have a signed distance: no function needed).
struct SideTest {
  std::optional<WindingNumber> winding;
  SideFunction side;
};

void make_side_test(const PipelineConfig& c, const PlacedSurface& placed, double h, SideTest& test) {
  if (parse_wall_offset(c.offset) == WallOffset::centered || placed.input.kind == "shape") return;
  if (!placed.mesh)
    throw InputError(
        "--offset " + c.offset +
        " needs a triangle mesh or shape input to tell inside from outside: use --offset centered");
  test.winding.emplace(*placed.mesh);
  const double step = 0.25 * h;
  test.side = [&winding = *test.winding, step](const Vec3& x, const Vec3& cp) {
    return side_of_surface(winding, x, cp, step);
  };
}

// The shell's samples: wall and offset from mm to grid units.
ShellSamples sample_printable_shell(const PipelineConfig& c, const PlacedSurface& placed,
                                    const NarrowBand& band, std::span<const double> phi,
                                    const SideFunction& side, PipelineResult& result) {
  const auto start = std::chrono::steady_clock::now();
  const double mm_per_grid = placed.mm_per_grid();
  ShellOptions options;
  options.thickness = result.solid.wall_mm / mm_per_grid;
  options.offset = parse_wall_offset(c.offset);
  options.pattern_length = 4.0 * std::sqrt(2.0) * result.model.epsilon;  // see shell.hpp
  options.side = side;
  ShellSamples samples = sample_shell(*placed.surface, band, phi, options);
  SolidSummary& s = result.solid;
  s.spacing_mm = samples.grid.h() * mm_per_grid;
  s.samples = samples.points.size();
  s.incomplete_stencils = samples.incomplete_stencils;
  s.seconds_sample = seconds_since(start);
  return samples;
}

// Probes across the shell's wall (mm) at up to `count` band voxels well inside the solid (phi nearer
// its minimum than the pore level, so away from pore rims, where a probe would graze the rim's wall),
// spread by band order.
std::vector<WallProbe> wall_probes(const PlacedSurface& placed, const NarrowBand& band,
                                   std::span<const double> phi, double iso, double wall_mm, WallOffset offset,
                                   const SideFunction& side) {
  std::vector<WallProbe> probes;
  const std::size_t count = 256, stride = std::max<std::size_t>(1, band.size() / (4 * count));
  const double h = band.grid().h();
  const double below = 0.5 * (iso + *std::min_element(phi.begin(), phi.end()));
  for (std::size_t v = 0; v < band.size() && probes.size() < count; v += stride) {
    if (!(phi[v] < below)) continue;
    const Vec3 x = band.grid().position(band.voxels()[v]);
    const std::optional<Vec3> cp = closest_point_at(*placed.surface, x, h, ClosestPointRule::exact);
    if (!cp || (x - *cp).norm() < 0.25 * h) continue;  // the normal is only defined off the surface
    // The mirror point across the surface must share the closest point, else cp is on an open edge or
    // the surface folds within h: the line along x - cp would not cross the wall.
    const std::optional<Vec3> mirror =
        closest_point_at(*placed.surface, 2.0 * *cp - x, h, ClosestPointRule::exact);
    if (!mirror || (*mirror - *cp).norm() > 0.25 * h) continue;
    Vec3 n = (x - *cp).normalized();
    if (offset != WallOffset::centered) {
      const double outside = side ? side(x, *cp) : placed.surface->distance(x);
      if (outside == 0.0) continue;
      if (outside < 0.0) n = -n;
    }
    const double centre = offset == WallOffset::centered ? 0.0 : (offset == WallOffset::outside ? 0.5 : -0.5);
    probes.push_back({placed.to_mm(*cp) + centre * wall_mm * n, n});
  }
  return probes;
}

// The model on this grid: the hole map's (eps from the spacing, dt from eps^2) or the paper's
// (eps_m from h, dt = K h).
void set_model(const PipelineConfig& c, const PlacedSurface& placed, const Grid& grid,
               PipelineResult& result) {
  if (!result.plan) {
    result.model = ModelParameters{c.alpha, epsilon_m(c.epsilon_m, grid.h()), c.phi_bar};
    result.dt = c.dt_in_h * grid.h();
    return;
  }
  const HoleCalibration& cal = hole_calibration();
  const double eps = result.plan->epsilon / placed.mm_per_grid();
  result.model = ModelParameters{cal.kappa / (eps * eps), eps, result.plan->phi_bar};
  result.dt = cal.dt_per_epsilon_squared * eps * eps;
}

// Hole statistics at one level in millimetres.
HoleStats holes_in_mm(const NarrowBand& band, std::span<const double> phi, double level,
                      const PlacedSurface& placed) {
  const double mm_per_grid = placed.mm_per_grid();
  HoleStats s = hole_statistics(band, phi, level);
  for (Hole& hole : s.holes) {
    hole.centroid = placed.to_mm(hole.centroid);
    hole.area *= mm_per_grid * mm_per_grid;
    hole.diameter *= mm_per_grid;
  }
  s.diameter_mean *= mm_per_grid;
  s.spacing_mean *= mm_per_grid;
  return s;
}

// The hole table of one output (mm): each band hole's centroid seeds a cut through the wall's middle (the
// surface itself for the narrow volume), reaching its band diameter and two of the solid's cells beyond.
HoleTable hole_table(const TriangleMesh& mesh_mm, const HoleStats& holes_mm, const PipelineConfig& c,
                     const PlacedSurface& placed, const PipelineResult& result, const SideFunction& side) {
  if (holes_mm.holes.empty()) return {};
  const double mm = placed.mm_per_grid();
  // Normals point outward: a mesh's winding number also where a centred wall did not need it.
  std::optional<WindingNumber> winding;
  SideFunction outward = side;
  if (!outward && placed.mesh) {
    winding.emplace(*placed.mesh);
    outward = [&w = *winding, step = 0.25 * result.h](const Vec3& x, const Vec3& cp) {
      return side_of_surface(w, x, cp, step);
    };
  }
  const SurfaceMidWall mid_wall(*placed.surface, result.h, result.solid.wall_mm / mm,
                                c.mode == "shell" ? parse_wall_offset(c.offset) : WallOffset::centered,
                                outward, mm, placed.to_mm(Vec3::Zero()));
  std::vector<Vec3> centres;
  std::vector<double> reach;
  for (const Hole& hole : holes_mm.holes) {
    centres.push_back(hole.centroid);
    reach.push_back(hole.diameter + 2.0 * result.solid.spacing_mm);
  }
  return measure_holes(mesh_mm, seeds_near(mid_wall, centres, reach), &mid_wall);
}

// A scalar painted on the input mesh (a PLY vertex property), as a function of a point in mm: its value
// at the closest point on the file's faces. Read before the solve, so a bad file fails at once.
std::function<double(const Vec3&)> input_field(const PipelineConfig& c, const PlacedSurface& placed,
                                               const std::string& property, const std::string& option) {
  if (c.mesh.empty() || lowercase_extension(c.mesh) != ".ply")
    throw InputError(option +
                     " reads a vertex property of the input mesh: give the mesh as a PLY file with a '" +
                     property + "' vertex property (--mesh FILE.ply)");
  auto field = std::make_shared<const VertexScalarField>(VertexScalarField::read_ply(c.mesh, property));
  const double mm_per_unit = placed.input.millimetres_per_unit;
  return [field, mm_per_unit](const Vec3& x_mm) { return field->at(x_mm / mm_per_unit); };
}

// Per band voxel, how solid the wall must stay (0 free, 1 solid): rims, keep-out spheres and a keep-out
// mask (a 0/1 vertex property, blended over 0.25-0.75). Empty where nothing is kept out.
std::vector<double> solid_zones(const PipelineConfig& c, const PlacedSurface& placed, const NarrowBand& band,
                                double epsilon) {
  if (c.rim_mm <= 0.0 && c.keep_out.empty() && c.keep_out_boxes.empty() && c.keep_out_mask.empty()) return {};
  const double grid_per_mm = 1.0 / placed.mm_per_grid();
  std::vector<KeepOutSphere> spheres;
  for (const auto& k : c.keep_out)
    spheres.push_back({placed.from_mm(Vec3(k[0], k[1], k[2])), k[3] * grid_per_mm});
  const std::vector<Segment> boundary =
      placed.mesh ? boundary_segments(*placed.mesh) : std::vector<Segment>{};
  // The ramp lets the pattern meet the zone over about one interface width.
  std::vector<KeepOutBox> boxes;
  for (const auto& k : c.keep_out_boxes) {
    const Vec3 a = placed.from_mm(Vec3(k[0], k[1], k[2])), b = placed.from_mm(Vec3(k[3], k[4], k[5]));
    boxes.push_back({a.cwiseMin(b), a.cwiseMax(b)});
  }
  std::vector<double> weight =
      solid_zone_weight(band, boundary, c.rim_mm * grid_per_mm, spheres, 2.0 * epsilon, boxes);
  if (!c.keep_out_mask.empty()) {
    const auto mask = input_field(c, placed, c.keep_out_mask, "--keep-out-mask");
    for (std::size_t v = 0; v < band.size(); ++v) {
      const double m = mask(placed.to_mm(band.grid().position(band.voxels()[v])));
      weight[v] = std::max(weight[v], std::clamp(2.0 * (m - 0.25), 0.0, 1.0));
    }
  }
  return weight;
}

// A voxel size up to this factor above the hole map's keeps the pattern's interface resolved
// (eps >= 0.77 h); coarser grids change the spacing.
constexpr double kCoarsestVoxelPerPlanned = 1.25;

// Hole-size grading: phi shifted per voxel so that {phi > level} has the graded holes.
void grade_holes(const GradeSpec& grade, const std::function<double(const Vec3&)>& field,
                 const PlacedSurface& placed, const NarrowBand& band, std::vector<double>& phi,
                 PipelineResult& result) {
  Box bounds{Vec3::Constant(std::numeric_limits<double>::infinity()),
             Vec3::Constant(-std::numeric_limits<double>::infinity())};
  std::vector<Vec3> positions(band.size());
  for (std::size_t v = 0; v < band.size(); ++v) {
    positions[v] = placed.to_mm(band.grid().position(band.voxels()[v]));
    bounds.min = bounds.min.cwiseMin(positions[v]);
    bounds.max = bounds.max.cwiseMax(positions[v]);
  }
  const PatternPlan& plan = *result.plan;
  const auto diameter_at = graded_diameter(grade, bounds, plan.diameter, field);
  result.grading = apply_grading(phi, positions, plan.spacing, plan.level, diameter_at);
}

// What a slicer needs, checked on the mesh as it will be written; throws naming every failed check.
void check_printable(const MeshTopology& t, double iso) {
  const std::string at = "the solid at iso " + std::to_string(iso);
  if (t.triangles == 0) throw std::runtime_error(at + " is empty: choose a level above min(phi)");
  std::string failed;
  const auto fail = [&](std::int64_t count, const char* what) {
    if (count != 0) failed += (failed.empty() ? "" : ", ") + std::to_string(count) + " " + what;
  };
  fail(t.boundary_edges, "boundary edges");
  fail(t.nonmanifold_edges + t.nonmanifold_vertices, "non-manifold edges or vertices");
  fail(t.misoriented_edges, "inconsistently oriented edges");
  fail(t.degenerate_triangles, "degenerate triangles");
  if (!(t.signed_volume > 0.0)) failed += (failed.empty() ? "" : ", ") + std::string("volume not positive");
  if (!failed.empty())
    throw std::runtime_error(at + " failed the printability check (" + failed +
                             "); nothing was written. Please report this as a bug");
}

}  // namespace

std::filesystem::path output_path_for_level(const std::filesystem::path& output, double iso, bool several) {
  if (!several) return output;
  std::ostringstream name;
  name << output.stem().string() << "-iso" << iso << output.extension().string();
  return output.parent_path() / name.str();
}

namespace {

// The band's values and its ghosts (outside: 1) as a field on the band's grid.
template <class Use>
auto with_narrow_volume_field(const NarrowBand& band, std::span<const double> phi, const Use& use) {
  std::vector<Coord> points(band.voxels().begin(), band.voxels().end());
  points.insert(points.end(), band.ghosts().begin(), band.ghosts().end());
  std::vector<double> values(phi.begin(), phi.end());
  values.resize(points.size(), 1.0);
  return use(SparseField{&band.grid(), points, values, 1.0});
}

// The solve stage: the model on this grid, the initial state (or the coarse start's carried pattern),
// the run to the steady state. Returns phi on the band.
std::vector<double> solve_pattern(const PipelineConfig& config, const PlacedSurface& placed, const Grid& grid,
                                  const NarrowBand& band, PipelineResult& result) {
  set_model(config, placed, grid, result);
  const auto t = std::chrono::steady_clock::now();
  // The initial state on a band: noise about phi_bar, solid zones (rims along open boundaries, keep-out
  // spheres and masks) solid and held there by a local mean concentration. Without noise: the mean
  // field alone, for a band that starts from a carried pattern.
  const auto level_start = [&](const NarrowBand& b, bool noise) {
    LevelStart s;
    const std::vector<double> weight = solid_zones(config, placed, b, result.model.epsilon);
    if (!weight.empty()) s.mean_field = mean_concentration_field(weight, result.model.phi_bar);
    if (!noise) return s;
    s.phi = random_initial_condition(b, result.model.phi_bar, config.amplitude, config.seed);
    for (std::size_t v = 0; v < weight.size(); ++v) s.phi[v] = (1.0 - weight[v]) * s.phi[v] - weight[v];
    return s;
  };
  RunOptions run_options;
  run_options.max_steps = config.max_steps;
  run_options.tolerance = config.tolerance;
  run_options.energy_every = config.energy_every;
  // Separated phases span about [-1, 1]; the decayed noise of the quiet phase spans far less.
  if (uniform_state_unstable(result.model.alpha, result.model.epsilon, result.model.phi_bar))
    run_options.min_spread = 1.0;
  run_options.on_step = config.on_step;
  const std::optional<Grid> coarse_grid = config.solver == "fast" && config.coarse_start
                                              ? pattern_grid(*placed.surface, grid.h(), result.model.epsilon)
                                              : std::nullopt;
  LevelStart fine_start = level_start(band, !coarse_grid);
  if (coarse_grid) {
    CoarseStartOptions coarse{[&](const NarrowBand& b) { return level_start(b, true); }, run_options,
                              config.fast};
    coarse.run.energy_every = 0;
    if (config.on_step)
      coarse.run.on_step = [&](const StepProgress& p) {
        StepProgress tagged = p;
        tagged.coarse = true;
        config.on_step(tagged);
      };
    result.coarse_start.emplace();
    fine_start.phi = coarse_start(*placed.surface, *coarse_grid, band, result.model, result.dt, coarse,
                                  *result.coarse_start);
    release_free_memory();
  }
  std::vector<double>& phi = fine_start.phi;
  std::unique_ptr<TimeStepper> solver;
  if (config.solver == "reference") {
    solver = std::make_unique<ReferenceSolver>(band, result.model, result.dt, config.inner);
    result.inner_iteration = to_string(config.inner.method);
  } else {
    auto fast = std::make_unique<FastSolver>(band, result.model, result.dt, config.fast);
    if (!fine_start.mean_field.empty()) fast->set_mean_field(std::move(fine_start.mean_field));
    result.solver_bytes = fast->memory_bytes();
    solver = std::move(fast);
    result.inner_iteration = "multigrid";
  }
  result.solver_name = solver->name();
  // The energy's Poisson factorisation costs about 6 s at 73k band voxels and 70 s / 2 GB at 290k:
  // --energy-every 0 skips it for large runs.
  std::optional<EnergyFunctional> energy;
  if (config.energy_every > 0) energy.emplace(band, result.model);
  result.run = run_to_steady_state(*solver, phi, energy ? &*energy : nullptr, run_options);
  // The solver's hierarchy and the energy's factorisation are done with: free them before meshing,
  // the stage with the largest footprint.
  solver.reset();
  energy.reset();
  release_free_memory();
  result.seconds_solve = seconds_since(t);
  result.peak_rss_after_solve = peak_rss_bytes();
  if (!std::isfinite(result.run.final_ec))
    throw std::runtime_error("the solver diverged (non-finite values)");
  return std::move(phi);
}

}  // namespace

TriangleMesh narrow_volume_mesh(const NarrowBand& band, std::span<const double> phi, double iso) {
  return with_narrow_volume_field(band, phi,
                                  [&](const SparseField& f) { return extract_isosurface(f, iso); });
}

std::int64_t narrow_volume_euler(const NarrowBand& band, std::span<const double> phi, double iso) {
  return with_narrow_volume_field(
      band, phi, [&](const SparseField& f) { return isosurface_euler_characteristic(f, iso); });
}

PipelineResult run_pipeline(const PipelineConfig& given) {
  validate(given);
  keep_large_blocks_mapped();
  const auto start = std::chrono::steady_clock::now();
  PipelineResult result;
  result.threads =
      static_cast<int>(tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism));
  PipelineConfig config = given;
  result.requested_holes = given.holes;
  if (!config.holes.empty()) {
    result.plan = plan_pattern(config.holes);
    if (config.voxel_size <= 0.0) {
      config.voxel_size = result.plan->voxel_size;
    } else if (config.voxel_size > kCoarsestVoxelPerPlanned * result.plan->voxel_size) {
      throw InputError("--voxel-size " + std::to_string(config.voxel_size) +
                       " mm is too coarse for holes at " + std::to_string(result.plan->spacing) +
                       " mm spacing: use at most " +
                       std::to_string(kCoarsestVoxelPerPlanned * result.plan->voxel_size) +
                       " mm, or leave --voxel-size out (" + std::to_string(result.plan->voxel_size) + " mm)");
    }
    config.iso_levels = {result.plan->level};
    config.phi_bar = result.plan->phi_bar;
  }

  auto t = std::chrono::steady_clock::now();
  const PlacedSurface placed = place_surface(config);
  result.input = placed.input;
  result.solid.mode = config.mode;
  result.seconds_input = seconds_since(t);
  const Grid grid = Grid::fitted(placed.domain, placed.resolution);
  result.grid_dims = grid.dims();
  result.h = grid.h();
  check_memory(config, placed, grid.h() * placed.mm_per_grid());
  // The wall: asked for (shell), or the band's width 2 delta (the default shell, the narrow volume).
  result.solid.wall_mm = config.mode == "shell" && config.wall > 0.0
                             ? config.wall
                             : 2.0 * BandOptions{}.delta_in_h * grid.h() * placed.mm_per_grid();
  if (config.max_triangles > 0 && config.max_deviation > 0.25 * result.solid.wall_mm)
    throw InputError("--max-deviation " + std::to_string(config.max_deviation) +
                     " mm is more than a quarter of the " + std::to_string(result.solid.wall_mm) +
                     " mm wall: the reduced wall's two sides could meet; use at most " +
                     std::to_string(0.25 * result.solid.wall_mm) + " mm");
  std::function<double(const Vec3&)> grade_field;
  if (config.grade && config.grade->kind == GradeSpec::Kind::field)
    grade_field =
        input_field(config, placed, config.grade->property, "--grade field:" + config.grade->property);

  t = std::chrono::steady_clock::now();
  // Optional so that shell mode can free it before meshing, the stage with the largest footprint.
  std::optional<NarrowBand> band_storage(build_band(*placed.surface, grid));
  const NarrowBand& band = *band_storage;
  release_free_memory();
  result.seconds_band = seconds_since(t);
  result.peak_rss_after_band = peak_rss_bytes();
  result.band_voxels = band.size();
  result.ghosts = band.ghost_count();
  result.band_stats = band.stats();
  result.band_bytes = band.memory_bytes();

  std::vector<double> phi = solve_pattern(config, placed, grid, band, result);
  result.spots = spot_statistics(band, phi, 0.0);

  // Build and check every mesh before writing any, so a failed check leaves no output at all.
  t = std::chrono::steady_clock::now();
  if (config.grade) grade_holes(*config.grade, grade_field, placed, band, phi, result);
  SideTest side;
  const bool shell_mode = config.mode == "shell";
  std::optional<ShellSamples> shell;  // freed once the last level is meshed
  if (shell_mode) {
    make_side_test(config, placed, grid.h(), side);
    shell = sample_printable_shell(config, placed, band, phi, side.side, result);
  } else {
    result.solid.spacing_mm = grid.h() * placed.mm_per_grid();
  }
  result.solid.offset = config.offset;
  // What the band and phi tell about each level, before meshing: in shell mode the band is then freed
  // (half a gigabyte at 6 M band voxels), as the meshes need only the shell's samples.
  const bool several = config.iso_levels.size() > 1;
  for (double iso : config.iso_levels) {
    MeshOutput out;
    out.iso = iso;
    out.path = output_path_for_level(config.output, iso, several);
    out.holes = holes_in_mm(band, phi, iso, placed);
    out.spots_at_iso = static_cast<std::int64_t>(out.holes.holes.size());  // every spot is a hole
    result.meshes.push_back(out);
  }
  std::vector<std::vector<WallProbe>> probes;
  if (shell_mode) {
    for (double iso : config.iso_levels)
      probes.push_back(wall_probes(placed, band, phi, iso, result.solid.wall_mm,
                                   parse_wall_offset(config.offset), side.side));
    phi = {};
    band_storage.reset();  // `band` is not used below in shell mode
    release_free_memory();
  }
  // The unperforated solid gives the reference Euler characteristic: each pore is one tunnel, so
  // pores = (chi0 - chi) / 2. Computed, not derived from the input's topology, because the band closes
  // holes narrower than about 2 delta (a scan's small holes) and may merge close sheets; counted from the
  // samples (isosurface_euler_characteristic), not from a mesh that is not written.
  if (shell_mode) {
    result.unperforated_euler = unperforated_shell_euler(*shell);
  } else {
    const std::vector<double> solid(band.size(), -1.0);
    result.unperforated_euler = narrow_volume_euler(band, solid, 0.0);
  }
  std::vector<TriangleMesh> meshes;
  for (std::size_t level = 0; level < config.iso_levels.size(); ++level) {
    MeshOutput& out = result.meshes[level];
    meshes.push_back(shell_mode ? shell_mesh(*shell, out.iso) : narrow_volume_mesh(band, phi, out.iso));
    if (level + 1 == config.iso_levels.size()) shell.reset();  // the samples, before the checks
    for (Vec3& v : meshes.back().vertices) v = placed.to_mm(v);
    if (config.max_triangles > 0)
      out.reduction = decimate_mesh(meshes.back(), {config.max_triangles, config.max_deviation});
    out.topology = analyze_topology(meshes.back());
    out.pores_from_euler = (result.unperforated_euler - out.topology.euler_characteristic) / 2;
    check_printable(out.topology, out.iso);
    if (shell_mode) out.wall = measure_wall(meshes.back(), probes[level], 4.0 * result.solid.wall_mm);
    out.hole_table = hole_table(meshes.back(), out.holes, config, placed, result, side.side);
  }
  for (std::size_t i = 0; i < meshes.size(); ++i) write_mesh(result.meshes[i].path, meshes[i]);
  result.seconds_mesh = seconds_since(t);
  result.seconds_total = seconds_since(start);
  result.peak_rss_total = peak_rss_bytes();
  return result;
}

}  // namespace poreshell
