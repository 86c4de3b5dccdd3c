#include "pipeline/pipeline.hpp"

#include <fmt/core.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

#include "core/error.hpp"
#include "core/heap.hpp"
#include "geometry/printability.hpp"
#include "geometry/refine.hpp"
#include "input/vertex_field.hpp"
#include "measure/wall_probes.hpp"
#include "pattern/grading.hpp"
#include "pattern/layout.hpp"
#include "pattern/solid_zones.hpp"
#include "pattern/spot_rules.hpp"
#include "pipeline/run_cost.hpp"
#include "pipeline/validate.hpp"
#include "shell/narrow_volume.hpp"
#include "shell/shell.hpp"
#include "solver/solve.hpp"

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

// Hole statistics at one level in millimetres. The holes' Voronoi cells cover the free surface only: a
// hole beside a solid zone (a rim, an ear) would otherwise own the zone's area too.
HoleStats hole_stats_mm(const NarrowBand& band, std::span<const double> phi, double level,
                        const PlacedSurface& placed, std::span<const double> zone_weight) {
  const double mm_per_grid = placed.mm_per_grid();
  HoleStats s = hole_statistics(band, phi, level);
  std::vector<Vec3> centres;
  for (const BandHole& hole : s.holes) centres.push_back(hole.centre);
  s.cell_area_cv = cell_area_cv(area_samples(band, zone_weight), centres);
  for (BandHole& hole : s.holes) {
    hole.centroid = placed.to_mm(hole.centroid);
    hole.centre = placed.to_mm(hole.centre);
    hole.area *= mm_per_grid * mm_per_grid;
    hole.diameter *= mm_per_grid;
    hole.nearest *= mm_per_grid;
  }
  s.diameter_mean *= mm_per_grid;
  s.spacing_mean *= mm_per_grid;
  return s;
}

// The shell's samples: wall and offset from mm to grid units.
ShellSamples sample_printable_shell(const Options& c, const PlacedSurface& placed, const NarrowBand& band,
                                    std::span<const double> phi, const SideFunction& side,
                                    PipelineResult& result, const StageProgress& progress) {
  const auto start = std::chrono::steady_clock::now();
  const double mm_per_grid = placed.mm_per_grid();
  ShellOptions options;
  options.thickness = result.solid.wall_mm / mm_per_grid;
  options.offset = c.offset;
  options.pattern_length = 4.0 * std::sqrt(2.0) * result.model.epsilon;  // see shell.hpp
  options.side = side;
  options.open_mesh = placed.open_mesh();
  options.progress = progress;
  ShellSamples samples = sample_shell(*placed.surface, band, phi, options);
  SolidSummary& s = result.solid;
  s.spacing_mm = samples.grid.h() * mm_per_grid;
  s.samples = samples.points.size();
  s.incomplete_stencils = samples.incomplete_stencils;
  s.seconds_sample = seconds_since(start);
  return samples;
}

// A preview's output: the surface with phi at each vertex, and the band's holes. A mesh input is shown
// as itself (preview_surface_mesh: the user's own triangles, and points clicked on it lie on the
// surface); other inputs as a thin slab of the band ({|psi| < h}, closed at the band's resolution).
void preview_output(double level, const Options& options, const PlacedSurface& placed, const NarrowBand& band,
                    std::span<const double> phi, std::span<const double> zone_weight, PipelineResult& result,
                    RunMonitor& monitor) {
  monitor.stage("mesh");
  const auto t = std::chrono::steady_clock::now();
  MeshOutput out;
  out.iso = level;
  out.holes = hole_stats_mm(band, phi, level, placed, zone_weight);
  out.spots_at_iso = static_cast<std::int64_t>(out.holes.holes.size());
  std::vector<HoleDisc> discs;
  for (const BandHole& h : out.holes.holes) discs.push_back({h.centre, h.diameter});
  out.zones = check_zones(discs, options, placed);
  out.mesh = placed.mesh ? preview_surface_mesh(*placed.mesh, band.grid().h()) : surface_slab_mesh(band);
  monitor.check();
  out.pattern.resize(out.mesh.vertices.size());
  tbb::parallel_for(std::size_t{0}, out.mesh.vertices.size(), [&](std::size_t v) {
    out.pattern[v] = interpolation_stencil(band, out.mesh.vertices[v]).interpolate(phi);
  });
  for (Vec3& v : out.mesh.vertices) v = placed.to_mm(v);
  result.solid.spacing_mm = band.grid().h() * placed.mm_per_grid();
  result.meshes.push_back(std::move(out));
  result.seconds_mesh = seconds_since(t);
}

// The output reduced within `max_deviation` (issue 49): as far as the bound allows by the fans' bounds
// alone, one attempt that keeps the bound everywhere (mesh_decimate.hpp); to a count, or `lean`, by
// placed collapses, which reach about half the triangles for several times the time.
void reduce_output(MeshOutput& out, const Options& options, double wall_mm, const StageProgress& progress) {
  const std::int64_t target = options.max_triangles > 0 ? options.max_triangles : 4;
  const DistanceRule rule =
      options.max_triangles > 0 || options.lean ? DistanceRule::kPlaced : DistanceRule::kBoundOnly;
  const DecimateOptions decimate{target, reduction_bound(options, wall_mm), progress, rule};
  try {
    out.reduction = decimate_mesh(out.mesh, decimate);
  } catch (const Error&) {
    throw;  // cancelled, or bad input: as anywhere else
  } catch (const std::runtime_error& failed) {
    // The default's reduction is an economy, never a reason to fail a run: where its result fails a
    // check (the mesh left as it was), the full isosurface is written. A budget's failure is the run's.
    if (options.max_triangles > 0) throw;
    out.reduction.reset();
    out.reduction_skipped = failed.what();  // said in the report's warnings: never silently
  }
  // A budget is a promise to the printer or the viewer downstream: not met, nothing is written.
  if (options.max_triangles > 0 && !out.reduction->reached_target)
    throw OptionError(
        "max_triangles",
        fmt::format("`max_triangles` {} cannot be met within `max_deviation` {:g} mm: the reduction "
                    "stopped at {} triangles, the fewest it reaches within that bound; ask for at least "
                    "{}, or allow a larger `max_deviation` (at most a quarter of the wall, {:g} mm)",
                    options.max_triangles, reduction_bound(options, wall_mm), out.reduction->triangles_after,
                    out.reduction->triangles_after, rounded_down(0.25 * wall_mm)));
}

}  // namespace

PreparedInput prepare_input(const Input& input, const Options& given) {
  validate(given);
  const auto start = std::chrono::steady_clock::now();
  PreparedInput prepared;
  prepared.given = given;
  Options& options = prepared.options;
  options = given;
  if (options.preview) options.coarse_start = false;
  if (holes_in_mm(options)) {
    prepared.plan = plan_pattern({given.hole_diameter, given.spacing, given.porosity});
    options.voxel_size = choose_voxel_size(options.voxel_size, *prepared.plan);
    // A preview runs on the pattern's own grid, never finer (so no coarse start).
    if (options.preview) options.voxel_size = std::max(options.voxel_size, prepared.plan->voxel_size);
    options.iso = {prepared.plan->level};
    options.phi_bar = prepared.plan->phi_bar;
  }
  prepared.placed = place_surface(input, options);
  // The default rim: half a hole along an open outline, so that none is cut open (issue 51). Closed
  // surfaces and the paper's parameters get none, so that their runs are as before.
  if (std::isnan(options.rim)) {
    const bool zones = prepared.plan && options.solver == SolverKind::fast && prepared.placed.open_mesh();
    options.rim = zones ? 0.5 * prepared.plan->diameter : 0.0;
  }
  prepared.seconds = seconds_since(start);
  return prepared;
}

PipelineResult run_pipeline(const Input& input, const Options& given, RunMonitor& monitor) {
  return run_pipeline(input, prepare_input(input, given), monitor);
}

PipelineResult run_pipeline(const Input& input, const PreparedInput& prepared, RunMonitor& monitor) {
  keep_large_blocks_mapped();
  // The run's clock counts the input's preparation too.
  const auto start =
      std::chrono::steady_clock::now() - std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                             std::chrono::duration<double>(prepared.seconds));
  PipelineResult result;
  result.threads = tbb::this_task_arena::max_concurrency();
  Options options = prepared.options;
  const Options& given = prepared.given;
  result.requested_holes = {given.hole_diameter, given.spacing, given.porosity};
  result.plan = prepared.plan;

  monitor.stage("input");
  auto t = std::chrono::steady_clock::now();
  const PlacedSurface& placed = prepared.placed;
  const FeatureZones features =
      result.plan ? feature_zones(options, placed, result.plan->diameter) : FeatureZones{};
  result.input = placed.input;
  result.input.thin_vertices = features.thin_vertices;
  result.input.crease_edges = features.crease_edges;
  result.solid.mode = options.mode == Mode::shell ? "shell" : "narrow-volume";
  result.seconds_input = prepared.seconds + seconds_since(t);
  const Grid grid = Grid::fitted(placed.domain, placed.resolution);
  result.grid_dims = grid.dims();
  result.h = grid.h();
  check_run_fits(estimate_run_cost(prepared, false), prepared);
  // The wall: asked for (shell); 2 mm where holes are asked in mm, so that it does not follow the hole
  // map's voxel; else the band's width 2 delta (the paper's parameters, the narrow volume).
  const WallChoice wall = choose_wall(options, result.plan.has_value(), grid.h() * placed.mm_per_grid());
  result.solid.wall_mm = wall.mm;
  result.solid.wall_source = wall.source;
  check_reduction(options, result.solid.wall_mm);
  const std::optional<Grade>& grade = options.grade;
  std::function<double(const Vec3&)> grade_field, mask;
  if (grade && grade->kind == Grade::Kind::field)
    grade_field = input_vertex_field(input, grade->field, "grade");
  if (!options.keep_out_mask.empty())
    mask = input_vertex_field(input, options.keep_out_mask, "keep_out_mask");

  monitor.stage("band");
  t = std::chrono::steady_clock::now();
  // Optional so that shell mode can free it before meshing, the stage with the largest footprint.
  BandOptions band_options;
  band_options.progress = StageProgress(monitor);
  // Measured on distances to meshes, shapes and splats; a sampled level set's gradient is its samples'.
  if (options.preview && placed.surface->closest_point_is_exact())
    band_options.gradient_bound = kLikelyGradientBound;
  band_options.surface_layer = builds_surface_layer(options, placed);
  std::optional<NarrowBand> band_storage(build_band(*placed.surface, grid, band_options));
  const NarrowBand& band = *band_storage;
  release_free_memory();
  result.seconds_band = seconds_since(t);
  result.peak_rss_after_band = peak_rss_bytes();
  result.band_voxels = band.size();
  result.ghosts = band.ghost_count();
  result.band_stats = band.stats();
  result.band_bytes = band.memory_bytes();
  result.zone_areas = zone_areas(options, placed, band, features, mask);

  monitor.stage("solve");
  t = std::chrono::steady_clock::now();
  const SolidZones zones = [&](const NarrowBand& b, double epsilon) {
    return solid_zones(options, placed, b, epsilon, mask, features);
  };
  SolveResult solved = solve_pattern(options, result.plan, placed, grid, band, zones, monitor);
  result.model = solved.model;
  result.dt = solved.dt;
  result.solver_name = solved.solver_name;
  result.inner_iteration = solved.inner_iteration;
  result.run = solved.run;
  result.coarse_start = solved.coarse_start;
  result.solver_bytes = solved.solver_bytes;
  result.seconds_solve = seconds_since(t);
  result.peak_rss_after_solve = peak_rss_bytes();
  result.stop_rule = solved.stop_rule;
  result.layout = solved.layout;
  result.layout_holes = solved.layout_holes;
  std::vector<double> phi = std::move(solved.phi);
  // A preview closes these too, and the discs the run would close (spot_rules.cpp); a surface
  // layer (band_options) also shows slivers of a disc's edge where it is a voxel thin.
  const bool unevolved = options.preview && result.run.steps == 0;  // the even layout's discs as placed
  if (result.plan) {
    const SpotRuleCounts fixed = apply_spot_rules(band, phi, *result.plan, placed, options.rim, unevolved);
    result.closed_small_holes = fixed.closed_small;
    result.rounded_oblong_holes = fixed.rounded_oblong;
    result.closed_oblong_holes = fixed.closed_oblong;
    result.closed_rim_holes = fixed.closed_in_rim;
  }
  result.spots = spot_statistics(band, phi, 0.0);
  // Before a preview's output too, so that it shows the sizes asked where they are asked: on the layout's
  // discs as placed, whose profile is not the equation's pores'.
  if (grade)
    result.grading =
        grade_holes(*grade, grade_field, placed, band, *result.plan, phi,
                    unevolved ? disc_levels(*result.plan) : LevelForRatio(level_for_diameter_ratio));
  if (options.preview) {
    preview_output(options.iso.front(), options, placed, band, phi, solved.zone_weight, result, monitor);
    result.seconds_total = seconds_since(start);
    result.peak_rss_total = peak_rss_bytes();
    monitor.advance(1.0, {}, 0, true);
    return result;
  }

  // Build and check every mesh before handing any out.
  monitor.stage("shell");
  t = std::chrono::steady_clock::now();
  SideTest side;
  const bool shell_mode = options.mode == Mode::shell;
  std::optional<ShellSamples> shell;  // freed once the last level is meshed
  if (shell_mode) {
    make_side_test(options.offset, placed, grid.h(), side);
    shell = sample_printable_shell(options, placed, band, phi, side.side, result,
                                   StageProgress(monitor, 0.0, 0.6));
  } else {
    result.solid.spacing_mm = grid.h() * placed.mm_per_grid();
  }
  result.solid.offset = to_string(options.offset);
  monitor.check();
  // What the band and phi tell about each level, before meshing: in shell mode the band is then freed
  // (half a gigabyte at 6 M band voxels), as the meshes need only the shell's samples.
  for (double iso : options.iso) {
    MeshOutput out;
    out.iso = iso;
    out.holes = hole_stats_mm(band, phi, iso, placed, solved.zone_weight);
    out.spots_at_iso = static_cast<std::int64_t>(out.holes.holes.size());  // every spot is a hole
    result.meshes.push_back(std::move(out));
    monitor.advance(0.65);
  }
  std::vector<std::vector<WallProbe>> probes;
  if (shell_mode) {
    for (double iso : options.iso)
      probes.push_back(wall_probes(placed, band, phi, iso, result.solid.wall_mm, options.offset, side.side));
    monitor.advance(0.7);
    phi = {};
    solved.zone_weight = {};
    band_storage.reset();  // `band` is not used below in shell mode
    release_free_memory();
  }
  // The unperforated solid gives the reference Euler characteristic: each pore is one tunnel, so
  // pores = (chi0 - chi) / 2. Computed, not derived from the input's topology, because the band closes
  // holes narrower than about 2 delta (a scan's small holes) and may merge close sheets; counted from the
  // samples (isosurface_euler_characteristic), not from a mesh that is not made.
  if (shell_mode) {
    result.unperforated_euler = unperforated_shell_euler(*shell, StageProgress(monitor, 0.7, 1.0));
  } else {
    const std::vector<double> solid(band.size(), -1.0);
    result.unperforated_euler = narrow_volume_euler(band, solid, 0.0);
  }
  monitor.stage("mesh");
  // For the voids' test below, past the samples, in a fraction of their bytes.
  const SolidWallPoints wall_solid = shell ? solid_wall_points(*shell) : SolidWallPoints{};
  for (std::size_t level = 0; level < options.iso.size(); ++level) {
    // Each level's share of the stage: the isosurface, the reduction if asked, the checks.
    const auto levels = static_cast<double>(options.iso.size());
    const StageProgress share(monitor, static_cast<double>(level) / levels,
                              static_cast<double>(level + 1) / levels);
    // By default the mesh is reduced as far as `max_deviation` allows (issue 49); `max_triangles` asks
    // for a count as well, and a reduction to a count starts from the chamfered surface (shell_mesh()).
    // The reduction costs several times the isosurface: it gets most of the share, so that the time
    // left said during it holds (docs/benchmarks.md "Time left during a reduction").
    const bool reducing = options.max_deviation > 0.0;
    const double meshed = reducing ? 0.15 : 0.6, reduced = reducing ? 0.95 : 0.6,
                 checked = reducing ? 0.97 : 0.9;
    MeshOutput& out = result.meshes[level];
    out.mesh = shell_mode ? shell_mesh(*shell, out.iso, share.part(0.0, meshed), options.max_triangles == 0)
                          : narrow_volume_mesh(band, phi, out.iso);
    if (level + 1 == options.iso.size()) shell.reset();  // the samples, before the checks
    share.advance(meshed);
    for (Vec3& v : out.mesh.vertices) v = placed.to_mm(v);
    // A cavity in a perforated solid is a pocket of the inside that no pore reaches: filled (issue 51).
    // Without pores the inside is the shell's own, kept; keep_fragments keeps everything.
    if (!options.keep_fragments)
      out.parts = keep_main_parts(out.mesh, options.min_part_fraction, out.spots_at_iso > 0);
    const std::int64_t wall_voids =
        shell_mode ? wall_voids_euler(out.parts, wall_solid, [&](const Vec3& p) { return placed.from_mm(p); })
                   : 0;
    if (reducing) reduce_output(out, options, result.solid.wall_mm, share.part(meshed, reduced));
    // A reduction checked its result already.
    out.topology = out.reduction && out.reduction->topology
                       ? *out.reduction->topology
                       : analyze_topology(out.mesh, share.part(reduced, checked));
    out.pores_from_euler = (result.unperforated_euler - wall_voids - out.topology.euler_characteristic) / 2;
    check_printable(out.topology, out.iso);
    share.advance(1.0);
  }
  // Every level is printable: now its holes and wall are measured on the mesh (the stage `holes` that
  // Progress documents; it reads only the meshes, the probes and the placement).
  monitor.stage("holes");
  for (std::size_t level = 0; level < options.iso.size(); ++level) {
    MeshOutput& out = result.meshes[level];
    if (shell_mode) out.wall = measure_wall(out.mesh, probes[level], 4.0 * result.solid.wall_mm);
    monitor.check();
    out.hole_table = output_hole_table(out.mesh, out.holes, placed, grid.h(), result.solid.wall_mm,
                                       result.solid.spacing_mm,
                                       shell_mode ? options.offset : WallOffset::centered, side.side);
    out.spots_at_open_edge = spots_at_open_edge(out.hole_table, out.holes, placed, result.solid.wall_mm);
    std::vector<HoleDisc> discs;
    for (const HoleRecord& h : out.hole_table.holes) discs.push_back({h.centre, h.diameter});
    out.zones = check_zones(discs, options, placed);
    monitor.advance(static_cast<double>(level + 1) / static_cast<double>(options.iso.size()));
  }
  result.seconds_mesh = seconds_since(t);
  result.seconds_total = seconds_since(start);
  result.peak_rss_total = peak_rss_bytes();
  monitor.advance(1.0, {}, 0, true);
  return result;
}

}  // namespace poreshell
