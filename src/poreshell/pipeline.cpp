#include "poreshell/pipeline.hpp"

#include <tbb/global_control.h>

#include <sys/resource.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <fstream>
#include <optional>
#include <sstream>

#include "poreshell/error.hpp"
#include "poreshell/initial_condition.hpp"
#include "poreshell/isosurface.hpp"
#include "poreshell/mesh_io.hpp"
#include "poreshell/mesh_surface.hpp"
#include "poreshell/mesh_writers.hpp"
#include "poreshell/point_cloud.hpp"
#include "poreshell/point_io.hpp"
#include "poreshell/point_segmentation.hpp"
#include "poreshell/shell.hpp"
#include "poreshell/solid_zones.hpp"
#include "poreshell/units.hpp"
#include "poreshell/winding_number.hpp"

namespace poreshell {
namespace {

// The process's peak resident set so far (Linux reports kilobytes).
std::size_t peak_rss_bytes() {
  rusage usage{};
  if (getrusage(RUSAGE_SELF, &usage) != 0) return 0;
  return static_cast<std::size_t>(usage.ru_maxrss) * 1024;
}

// Peak bytes of a whole run per band voxel, measured over the bunny scaling series (docs/benchmarks.md:
// 1.1-1.5 kB, the shell and its mesh included).
constexpr double kPeakBytesPerBandVoxel = 1300.0;

// MemAvailable from /proc/meminfo, else the physical memory.
double available_memory_bytes() {
  std::ifstream meminfo("/proc/meminfo");
  std::string key;
  double kib = 0.0;
  std::string unit;
  while (meminfo >> key >> kib >> unit)
    if (key == "MemAvailable:") return kib * 1024.0;
  return static_cast<double>(sysconf(_SC_PHYS_PAGES)) * static_cast<double>(sysconf(_SC_PAGE_SIZE));
}

// Refuses, before anything large is allocated, a run whose band would not fit in memory. The band is
// counted on a grid 8 times coarser (cheap: 1/64 of the voxels) and scaled by (h_coarse / h)^2, since a
// surface's band grows like its area over h^2.
void check_memory(const PipelineConfig& c, const Surface& surface, const Box& domain, int resolution,
                  double h_mm) {
  const double limit = c.max_memory_gb > 0.0 ? c.max_memory_gb * 1e9 : available_memory_bytes();
  const int coarse_points = (resolution - 1) / 8 + 1;
  if (coarse_points < 17) return;  // a small run: the estimate would be coarser than the run itself
  const double fine_h = (domain.max - domain.min).maxCoeff() / (resolution - 1);
  const double coarse_h = 8.0 * fine_h;
  Box padded{domain.min - Vec3::Constant(4 * coarse_h), domain.max + Vec3::Constant(4 * coarse_h)};
  const Grid coarse = Grid::fitted(
      padded, static_cast<int>(std::lround((padded.max - padded.min).maxCoeff() / coarse_h)) + 1);
  double voxels = 0.0;
  try {
    voxels = static_cast<double>(build_band(surface, coarse).size()) * std::pow(coarse.h() / fine_h, 2);
  } catch (const std::exception&) {
    return;  // no estimate on this grid: the run itself will say what is wrong
  }
  const double needed = voxels * kPeakBytesPerBandVoxel;
  if (needed <= limit) return;
  const double shrink = std::sqrt(limit / needed);
  std::ostringstream message;
  message.precision(3);
  message << "this run needs about " << needed / 1e9 << " GB (about " << voxels / 1e6
          << " million band voxels at h = " << h_mm << " mm), more than the " << limit / 1e9 << " GB "
          << (c.max_memory_gb > 0.0 ? "allowed by --max-memory" : "available") << ": use --resolution "
          << static_cast<int>(1 + (resolution - 1) * shrink) << " or less, or --voxel-size " << h_mm / shrink
          << " mm or more";
  throw InputError(message.str());
}

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// Grid cells between a mesh's bounding box and the grid's edge: the band (delta = 1.9 h) and its ghosts
// (one more cell) must stay inside the grid.
constexpr int kMeshPaddingCells = 4;

// The surface in grid coordinates. Meshes are scaled into the paper's frame: the grid's longest side
// has length 1, h = 1/(N - 1), so the paper's alpha, eps_m and dt = K h mean the same for any model;
// `to_input` maps results back to the file's units.
struct PlacedSurface {
  std::unique_ptr<Surface> surface;
  Box domain;
  InputSummary input;
  Vec3 input_center = Vec3::Zero();  // x_input = (x_grid - 0.5) / scale + input_center
  int resolution = 0;                // grid points along the longest side
  std::optional<TriangleMesh> mesh;  // a mesh input in grid coordinates: the shell's inside/outside test
};

// Grid points along the longest side: --resolution, or from --voxel-size over the longest extent.
int resolution_for(const PipelineConfig& c, double longest_extent, int padding_cells) {
  if (!(c.voxel_size > 0.0)) return c.resolution;
  const double voxel_size = c.voxel_size / millimetres_per_unit(c.units);  // in the input's units
  const double n = std::round(longest_extent / voxel_size) + 1 + 2 * padding_cells;
  if (n > 2048)
    throw InputError("--voxel-size needs " + std::to_string(static_cast<long long>(n)) +
                     " grid points along the longest side (at most 2048): choose a larger voxel size");
  if (n < 17) throw InputError("--voxel-size is too coarse for this model: choose a smaller voxel size");
  return static_cast<int>(n);
}

// Scales and centres `vertices` (a mesh's or a point cloud's) into the paper's frame, with padding, and
// sets the placement's resolution, scale, centre and domain.
void fit_to_unit_grid(std::vector<Vec3>& vertices, const PipelineConfig& c, const std::string& what,
                      PlacedSurface& placed) {
  Box box{vertices.front(), vertices.front()};
  for (const Vec3& v : vertices) {
    box.min = box.min.cwiseMin(v);
    box.max = box.max.cwiseMax(v);
  }
  const double longest = (box.max - box.min).maxCoeff();
  if (!(longest > 0.0)) throw InputError(what + " has zero size");
  placed.resolution = resolution_for(c, longest, kMeshPaddingCells);
  const double h = 1.0 / (placed.resolution - 1);
  const double scale = (1.0 - 2 * kMeshPaddingCells * h) / longest;
  placed.input.scale = scale;
  placed.input_center = 0.5 * (box.min + box.max);
  for (Vec3& v : vertices) v = (v - placed.input_center) * scale + Vec3::Constant(0.5);
  const Vec3 half = 0.5 * scale * (box.max - box.min) + Vec3::Constant(kMeshPaddingCells * h);
  placed.domain = Box{Vec3::Constant(0.5) - half, Vec3::Constant(0.5) + half};
}

// A point cloud: splats (direct) or the paper's densify-and-segment route, on the grid it will get.
void place_points(const PipelineConfig& c, PlacedSurface& placed) {
  PointCloud cloud = read_point_cloud(c.points);
  placed.input.kind = "points";
  placed.input.name = c.points.string();
  placed.input.vertices = static_cast<std::int64_t>(cloud.points.size());
  placed.input.triangles = static_cast<std::int64_t>(cloud.triangles.size());
  placed.input.point_route = c.point_route;
  fit_to_unit_grid(cloud.points, c, "the point cloud '" + c.points.string() + "'", placed);
  if (c.point_route == "direct") {
    placed.surface = std::make_unique<SplatSurface>(std::move(cloud.points));
    return;
  }
  SegmentationStats stats;
  placed.surface = segment_point_cloud(cloud.points, cloud.triangles,
                                       Grid::fitted(placed.domain, placed.resolution), {}, &stats);
  placed.input.densified_points = stats.points;
  placed.input.segmentation_iterations = stats.iterations;
}

PlacedSurface place_surface(const PipelineConfig& c) {
  PlacedSurface placed;
  if (!c.points.empty()) {
    place_points(c, placed);
    return placed;
  }
  if (c.mesh.empty()) {
    placed.surface = make_paper_shape(c.shape);
    placed.domain = Box{Vec3::Zero(), Vec3::Ones()};
    placed.input.kind = "shape";
    placed.input.name = c.shape;
    placed.input.euler_characteristic = c.shape == "torus" ? 0 : 2;
    placed.input_center = Vec3::Constant(0.5);  // the shapes are already in grid coordinates
    placed.resolution = resolution_for(c, 1.0, 0);
    return placed;
  }
  MeshInputStats stats;
  TriangleMesh mesh = read_triangle_mesh(c.mesh, &stats);
  placed.input = {"mesh",
                  c.mesh.string(),
                  stats.vertices,
                  stats.triangles,
                  stats.boundary_edges,
                  stats.dropped_degenerate,
                  analyze_topology(mesh).euler_characteristic,
                  1.0};
  fit_to_unit_grid(mesh.vertices, c, "the mesh '" + c.mesh.string() + "'", placed);
  placed.surface = std::make_unique<MeshSurface>(mesh);
  placed.mesh = std::move(mesh);
  return placed;
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
  if ((c.rim_mm > 0.0 || !c.keep_out.empty()) && c.solver != "fast")
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
  if (c.output.empty()) throw InputError("give an output file with -o OUT.stl");
  check_output_extension(c.output);
}

// The shell's samples: wall and offset from mm to grid units; the side of a mesh input from its
// winding number (shapes have a signed distance).
ShellSamples sample_printable_shell(const PipelineConfig& c, const PlacedSurface& placed,
                                    const NarrowBand& band, std::span<const double> phi,
                                    PipelineResult& result) {
  const auto start = std::chrono::steady_clock::now();
  const double mm_per_grid = result.input.millimetres_per_unit / result.input.scale;
  ShellOptions options;
  options.thickness = c.wall > 0.0 ? c.wall / mm_per_grid : 2.0 * BandOptions{}.delta_in_h * band.grid().h();
  options.offset = parse_wall_offset(c.offset);
  options.pattern_length = std::sqrt(2.0) * result.model.epsilon;  // unit slope across the interface
  std::optional<WindingNumber> winding;
  if (options.offset != WallOffset::centered && placed.input.kind != "shape") {
    if (!placed.mesh)
      throw InputError("--offset " + c.offset +
                       " needs a triangle mesh or shape input to tell inside from "
                       "outside: use --offset centered");
    winding.emplace(*placed.mesh);
    const double step = 0.25 * band.grid().h();
    options.side = [&winding, step](const Vec3& x, const Vec3& cp) {
      return side_of_surface(*winding, x, cp, step);
    };
  }
  ShellSamples samples = sample_shell(*placed.surface, band, phi, options);
  SolidSummary& s = result.solid;
  s.wall_mm = options.thickness * mm_per_grid;
  s.spacing_mm = samples.grid.h() * mm_per_grid;
  s.samples = samples.points.size();
  s.incomplete_stencils = samples.incomplete_stencils;
  s.seconds_sample = seconds_since(start);
  return samples;
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

TriangleMesh narrow_volume_mesh(const NarrowBand& band, std::span<const double> phi, double iso) {
  std::vector<Coord> points(band.voxels().begin(), band.voxels().end());
  points.insert(points.end(), band.ghosts().begin(), band.ghosts().end());
  std::vector<double> values(phi.begin(), phi.end());
  values.resize(points.size(), 1.0);
  const SparseField field{&band.grid(), points, values, 1.0};
  return extract_isosurface(field, iso);
}

PipelineResult run_pipeline(const PipelineConfig& config) {
  validate(config);
  const auto start = std::chrono::steady_clock::now();
  PipelineResult result;
  result.threads =
      static_cast<int>(tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism));

  auto t = std::chrono::steady_clock::now();
  const PlacedSurface placed = place_surface(config);
  result.input = placed.input;
  result.input.units = config.units;
  result.input.millimetres_per_unit = millimetres_per_unit(config.units);
  result.solid.mode = config.mode;
  result.seconds_input = seconds_since(t);
  const Grid grid = Grid::fitted(placed.domain, placed.resolution);
  result.grid_dims = grid.dims();
  result.h = grid.h();
  check_memory(config, *placed.surface, placed.domain, placed.resolution,
               grid.h() / placed.input.scale * millimetres_per_unit(config.units));

  t = std::chrono::steady_clock::now();
  const NarrowBand band = build_band(*placed.surface, grid);
  result.seconds_band = seconds_since(t);
  result.peak_rss_after_band = peak_rss_bytes();
  result.band_voxels = band.size();
  result.ghosts = band.ghost_count();
  result.band_stats = band.stats();
  result.band_bytes = band.memory_bytes();

  result.model = ModelParameters{config.alpha, epsilon_m(config.epsilon_m, grid.h()), config.phi_bar};
  result.dt = config.dt_in_h * grid.h();
  t = std::chrono::steady_clock::now();
  // Solid zones (rims along open boundaries, keep-out spheres) as a local mean concentration.
  const double grid_per_mm = placed.input.scale / millimetres_per_unit(config.units);
  std::vector<double> mean_field, solid_weight;
  if (config.rim_mm > 0.0 || !config.keep_out.empty()) {
    std::vector<KeepOutSphere> spheres;
    for (const auto& k : config.keep_out)
      spheres.push_back({(Vec3(k[0], k[1], k[2]) / millimetres_per_unit(config.units) - placed.input_center) *
                                 placed.input.scale +
                             Vec3::Constant(0.5),
                         k[3] * grid_per_mm});
    const std::vector<Segment> boundary =
        placed.mesh ? boundary_segments(*placed.mesh) : std::vector<Segment>{};
    // The ramp lets the pattern meet the zone over about one interface width.
    solid_weight =
        solid_zone_weight(band, boundary, config.rim_mm * grid_per_mm, spheres, 2.0 * result.model.epsilon);
    mean_field = mean_concentration_field(solid_weight, config.phi_bar);
  }
  std::unique_ptr<TimeStepper> solver;
  if (config.solver == "reference") {
    solver = std::make_unique<ReferenceSolver>(band, result.model, result.dt, config.inner);
    result.inner_iteration = to_string(config.inner.method);
  } else {
    auto fast = std::make_unique<FastSolver>(band, *placed.surface, result.model, result.dt, config.fast);
    if (!mean_field.empty()) fast->set_mean_field(mean_field);
    result.solver_bytes = fast->memory_bytes();
    solver = std::move(fast);
    result.inner_iteration = "multigrid";
  }
  result.solver_name = solver->name();
  // The energy's Poisson factorisation costs about 6 s at 73k band voxels and 70 s / 2 GB at 290k:
  // --energy-every 0 skips it for large runs.
  std::optional<EnergyFunctional> energy;
  if (config.energy_every > 0) energy.emplace(band, result.model);
  std::vector<double> phi = random_initial_condition(band, config.phi_bar, config.amplitude, config.seed);
  for (std::size_t v = 0; v < solid_weight.size(); ++v)  // solid zones start solid
    phi[v] = (1.0 - solid_weight[v]) * phi[v] + solid_weight[v] * -1.0;
  RunOptions run_options;
  run_options.max_steps = config.max_steps;
  run_options.tolerance = config.tolerance;
  run_options.energy_every = config.energy_every;
  // Separated phases span about [-1, 1]; the decayed noise of the quiet phase spans far less.
  if (uniform_state_unstable(result.model.alpha, result.model.epsilon, result.model.phi_bar))
    run_options.min_spread = 1.0;
  run_options.on_step = config.on_step;
  result.run = run_to_steady_state(*solver, phi, energy ? &*energy : nullptr, run_options);
  result.seconds_solve = seconds_since(t);
  result.peak_rss_after_solve = peak_rss_bytes();
  if (!std::isfinite(result.run.final_ec))
    throw std::runtime_error("the solver diverged (non-finite values)");
  result.spots = spot_statistics(band, phi, 0.0);

  // Build and check every mesh before writing any, so a failed check leaves no output at all.
  t = std::chrono::steady_clock::now();
  std::optional<ShellSamples> shell;
  if (config.mode == "shell") {
    shell = sample_printable_shell(config, placed, band, phi, result);
  } else {
    const double mm_per_grid = result.input.millimetres_per_unit / result.input.scale;
    result.solid.wall_mm = 2.0 * BandOptions{}.delta_in_h * grid.h() * mm_per_grid;
    result.solid.spacing_mm = grid.h() * mm_per_grid;
  }
  result.solid.offset = config.offset;
  // The unperforated solid gives the reference Euler characteristic: each pore is one tunnel, so
  // pores = (chi0 - chi) / 2. Computed, not derived from the input's topology, because the band closes
  // holes narrower than about 2 delta (a scan's small holes) and may merge close sheets.
  const std::vector<double> solid(band.size(), -1.0);
  result.unperforated_euler =
      analyze_topology(shell ? unperforated_shell_mesh(*shell) : narrow_volume_mesh(band, solid, 0.0))
          .euler_characteristic;
  const bool several = config.iso_levels.size() > 1;
  std::vector<TriangleMesh> meshes;
  for (double iso : config.iso_levels) {
    MeshOutput out;
    out.iso = iso;
    out.path = output_path_for_level(config.output, iso, several);
    meshes.push_back(shell ? shell_mesh(*shell, iso) : narrow_volume_mesh(band, phi, iso));
    for (Vec3& v : meshes.back().vertices)  // back to the input's frame, then to millimetres
      v = ((v - Vec3::Constant(0.5)) / result.input.scale + placed.input_center) *
          result.input.millimetres_per_unit;
    out.topology = analyze_topology(meshes.back());
    out.spots_at_iso = spot_statistics(band, phi, iso).count;
    out.pores_from_euler = (result.unperforated_euler - out.topology.euler_characteristic) / 2;
    check_printable(out.topology, iso);
    result.meshes.push_back(out);
  }
  for (std::size_t i = 0; i < meshes.size(); ++i) write_mesh(result.meshes[i].path, meshes[i]);
  result.seconds_mesh = seconds_since(t);
  result.seconds_total = seconds_since(start);
  result.peak_rss_total = peak_rss_bytes();
  return result;
}

}  // namespace poreshell
