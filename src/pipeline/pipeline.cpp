#include "pipeline/pipeline.hpp"

#include <fmt/core.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>
#include <utility>

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
#include "pipeline/solve_stage.hpp"
#include "pipeline/validate.hpp"
#include "shell/narrow_volume.hpp"
#include "shell/shell.hpp"

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
  options.pattern_length = 4.0 * std::sqrt(2.0) * result.solve.model.epsilon;  // see shell.hpp
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
void preview_output(double level, const ZoneOptions& zones, const PlacedSurface& placed,
                    const NarrowBand& band, std::span<const double> phi, std::span<const double> zone_weight,
                    PipelineResult& result, RunMonitor& monitor) {
  monitor.stage("mesh");
  const auto t = std::chrono::steady_clock::now();
  MeshOutput out;
  out.iso = level;
  out.holes = hole_stats_mm(band, phi, level, placed, zone_weight);
  out.spots_at_iso = static_cast<std::int64_t>(out.holes.holes.size());
  std::vector<HoleDisc> discs;
  for (const BandHole& h : out.holes.holes) discs.push_back({h.centre, h.diameter});
  out.zones = check_zones(discs, zones, placed);
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
// placed collapses, which reach about half the triangles for several times the time (a count the fans'
// bounds may reach, by them first).
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

// One run's stages in order (run_pipeline), and what each hands to the next.
class PipelineRun {
 public:
  PipelineRun(const Input& input, const PreparedInput& prepared, RunMonitor& monitor)
      : input_(input),
        prepared_(prepared),
        monitor_(monitor),
        placed_(prepared.placed),
        options_(prepared.options),
        zones_(zone_options(prepared.options)),
        // The run's clock counts the input's preparation too.
        start_(std::chrono::steady_clock::now() -
               std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                   std::chrono::duration<double>(prepared.seconds))) {
    result_.threads = tbb::this_task_arena::max_concurrency();
    const Options& given = prepared.given;
    result_.requested_holes = {given.hole_diameter, given.spacing, given.porosity};
    result_.plan = prepared.plan;
  }

  void read_input() {
    monitor_.stage("input");
    const auto t = std::chrono::steady_clock::now();
    features_ = result_.plan ? feature_zones(zones_, placed_, result_.plan->diameter) : FeatureZones{};
    result_.input = placed_.input;
    result_.input.thin_vertices = features_.thin_vertices;
    result_.input.crease_edges = features_.crease_edges;
    result_.solid.mode = options_.mode == Mode::shell ? "shell" : "narrow-volume";
    result_.seconds_input = prepared_.seconds + seconds_since(t);
    grid_.emplace(Grid::fitted(placed_.domain, placed_.resolution));
    result_.grid_dims = grid_->dims();
    result_.h = grid_->h();
    check_run_fits(estimate_run_cost(prepared_, false), prepared_);
    // The wall: asked for (shell); 2 mm where holes are asked in mm, so that it does not follow the hole
    // map's voxel; else the band's width 2 delta (the paper's parameters, the narrow volume).
    const WallChoice wall =
        choose_wall(options_, result_.plan.has_value(), grid_->h() * placed_.mm_per_grid());
    result_.solid.wall_mm = wall.mm;
    result_.solid.wall_source = wall.source;
    check_reduction(options_, result_.solid.wall_mm);
    if (options_.grade && options_.grade->kind == Grade::Kind::field)
      grade_field_ = input_vertex_field(input_, options_.grade->field, "grade");
    if (!options_.keep_out_mask.empty())
      mask_ = input_vertex_field(input_, options_.keep_out_mask, "keep_out_mask");
  }

  void build_band() {
    monitor_.stage("band");
    const auto t = std::chrono::steady_clock::now();
    BandOptions band_options;
    band_options.progress = StageProgress(monitor_);
    // Measured on distances to meshes, shapes and splats; a sampled level set's gradient is its samples'.
    if (options_.preview && placed_.surface->closest_point_is_exact())
      band_options.gradient_bound = kLikelyGradientBound;
    band_options.surface_layer = builds_surface_layer(options_, placed_);
    band_.emplace(poreshell::build_band(*placed_.surface, *grid_, band_options));
    release_free_memory();
    result_.seconds_band = seconds_since(t);
    result_.peak_rss_after_band = peak_rss_bytes();
    result_.band_voxels = band_->size();
    result_.ghosts = band_->ghost_count();
    result_.band_stats = band_->stats();
    result_.band_bytes = band_->memory_bytes();
    result_.zone_areas = zone_areas(zones_, placed_, *band_, features_, mask_);
  }

  void solve() {
    monitor_.stage("solve");
    const auto t = std::chrono::steady_clock::now();
    const NarrowBand& band = *band_;
    const SolidZones zones = [&](const NarrowBand& b, double epsilon) {
      return solid_zones(zones_, placed_, b, epsilon, mask_, features_);
    };
    solved_ = solve_pattern(solve_options(options_, result_.plan.has_value()), result_.plan, placed_, *grid_,
                            band, zones, monitor_);
    result_.solve = solved_;  // the summary: phi and the zone weights stay here
    result_.seconds_solve = seconds_since(t);
    result_.peak_rss_after_solve = peak_rss_bytes();
    phi_ = std::move(solved_.phi);
    // A preview closes these too, and the discs the run would close (spot_rules.cpp); a surface
    // layer (band_options) also shows slivers of a disc's edge where it is a voxel thin.
    const bool unevolved =
        options_.preview && result_.solve.run.steps == 0;  // the even layout's discs as placed
    if (result_.plan) {
      const SpotRuleCounts fixed =
          apply_spot_rules(band, phi_, *result_.plan, placed_, options_.rim, unevolved);
      result_.closed_small_holes = fixed.closed_small;
      result_.rounded_oblong_holes = fixed.rounded_oblong;
      result_.closed_oblong_holes = fixed.closed_oblong;
      result_.closed_rim_holes = fixed.closed_in_rim;
    }
    result_.spots = spot_statistics(band, phi_, 0.0);
    // Before a preview's output too, so that it shows the sizes asked where they are asked: on the layout's
    // discs as placed, whose profile is not the equation's pores'.
    if (options_.grade)
      result_.grading =
          grade_holes(*options_.grade, grade_field_, placed_, band, *result_.plan, phi_,
                      unevolved ? disc_levels(*result_.plan) : LevelForRatio(level_for_diameter_ratio));
  }

  PipelineResult preview() {
    preview_output(options_.iso.front(), zones_, placed_, *band_, phi_, solved_.zone_weight, result_,
                   monitor_);
    return finish();
  }

  // The shell's samples (shell mode), and what the band and phi tell about each level before meshing: in
  // shell mode the band is then freed (half a gigabyte at 6 M band voxels), as the meshes need only the
  // samples.
  void sample_shell() {
    monitor_.stage("shell");
    mesh_start_ = std::chrono::steady_clock::now();
    sample_levels(*band_);
    // The unperforated solid gives the reference Euler characteristic: each pore is one tunnel, so
    // pores = (chi0 - chi) / 2. Computed, not derived from the input's topology, because the band closes
    // holes narrower than about 2 delta (a scan's small holes) and may merge close sheets; counted from the
    // samples (isosurface_euler_characteristic), not from a mesh that is not made.
    if (shell_mode()) {
      phi_ = {};
      solved_.zone_weight = {};
      band_.reset();
      release_free_memory();
      result_.unperforated_euler = unperforated_shell_euler(*shell_, StageProgress(monitor_, 0.7, 1.0));
    } else {
      const std::vector<double> solid(band_->size(), -1.0);
      result_.unperforated_euler = narrow_volume_euler(*band_, solid, 0.0);
    }
  }

  // Every level meshed and checked before any is handed out.
  void mesh() {
    monitor_.stage("mesh");
    // For the voids' test, past the samples, in a fraction of their bytes.
    const SolidWallPoints wall_solid = shell_ ? solid_wall_points(*shell_) : SolidWallPoints{};
    const auto levels = static_cast<double>(options_.iso.size());
    for (std::size_t level = 0; level < options_.iso.size(); ++level) {
      // Each level's share of the stage: the isosurface, the reduction if asked, the checks.
      const StageProgress share(monitor_, static_cast<double>(level) / levels,
                                static_cast<double>(level + 1) / levels);
      mesh_level(result_.meshes[level], wall_solid, share, level + 1 == options_.iso.size());
    }
  }

  // Every level is printable: now its holes and wall are measured on the mesh (the stage `holes` that
  // Progress documents; it reads only the meshes, the probes and the placement).
  void measure_holes() {
    monitor_.stage("holes");
    for (std::size_t level = 0; level < options_.iso.size(); ++level) {
      MeshOutput& out = result_.meshes[level];
      if (shell_mode()) out.wall = measure_wall(out.mesh, probes_[level], 4.0 * result_.solid.wall_mm);
      monitor_.check();
      out.hole_table = output_hole_table(out.mesh, out.holes, placed_, grid_->h(), result_.solid.wall_mm,
                                         result_.solid.spacing_mm,
                                         shell_mode() ? options_.offset : WallOffset::centered, side_.side);
      out.spots_at_open_edge = spots_at_open_edge(out.hole_table, out.holes, placed_, result_.solid.wall_mm);
      std::vector<HoleDisc> discs;
      for (const HoleRecord& h : out.hole_table.holes) discs.push_back({h.centre, h.diameter});
      out.zones = check_zones(discs, zones_, placed_);
      monitor_.advance(static_cast<double>(level + 1) / static_cast<double>(options_.iso.size()));
    }
    result_.seconds_mesh = seconds_since(mesh_start_);
  }

  PipelineResult finish() {
    result_.seconds_total = seconds_since(start_);
    result_.peak_rss_total = peak_rss_bytes();
    monitor_.advance(1.0, {}, 0, true);
    return std::move(result_);
  }

 private:
  bool shell_mode() const { return options_.mode == Mode::shell; }

  // The shell's samples (shell mode), each level's holes and wall probes, from the band and phi.
  void sample_levels(const NarrowBand& band) {
    if (shell_mode()) {
      make_side_test(options_.offset, placed_, grid_->h(), side_);
      shell_ = sample_printable_shell(options_, placed_, band, phi_, side_.side, result_,
                                      StageProgress(monitor_, 0.0, 0.6));
    } else {
      result_.solid.spacing_mm = grid_->h() * placed_.mm_per_grid();
    }
    result_.solid.offset = to_string(options_.offset);
    monitor_.check();
    for (double iso : options_.iso) {
      MeshOutput out;
      out.iso = iso;
      out.holes = hole_stats_mm(band, phi_, iso, placed_, solved_.zone_weight);
      out.spots_at_iso = static_cast<std::int64_t>(out.holes.holes.size());  // every spot is a hole
      result_.meshes.push_back(std::move(out));
      monitor_.advance(0.65);
    }
    if (shell_mode()) {
      for (double iso : options_.iso)
        probes_.push_back(
            wall_probes(placed_, band, phi_, iso, result_.solid.wall_mm, options_.offset, side_.side));
      monitor_.advance(0.7);
    }
  }

  // One level (`last`: the samples are freed after it): the isosurface (from the shell's samples, or the
  // narrow volume's band), in mm, its cavities filled, reduced, checked printable, its pores counted.
  void mesh_level(MeshOutput& out, const SolidWallPoints& wall_solid, const StageProgress& share, bool last) {
    // By default the mesh is reduced as far as `max_deviation` allows (issue 49); `max_triangles` asks
    // for a count as well, and a reduction to a count starts from the chamfered surface (shell_mesh()).
    // The reduction costs several times the isosurface: it gets most of the share, so that the time
    // left said during it holds (docs/benchmarks.md "Time left during a reduction").
    const bool reducing = options_.max_deviation > 0.0;
    const double meshed = reducing ? 0.15 : 0.6, reduced = reducing ? 0.95 : 0.6,
                 checked = reducing ? 0.97 : 0.9;
    out.mesh = shell_mode()
                   ? shell_mesh(*shell_, out.iso, share.part(0.0, meshed), options_.max_triangles == 0)
                   : narrow_volume_mesh(*band_, phi_, out.iso);
    if (last) shell_.reset();  // the samples, before the checks
    share.advance(meshed);
    for (Vec3& v : out.mesh.vertices) v = placed_.to_mm(v);
    // A cavity in a perforated solid is a pocket of the inside that no pore reaches: filled (issue 51).
    // Without pores the inside is the shell's own, kept; keep_fragments keeps everything.
    if (!options_.keep_fragments)
      out.parts = keep_main_parts(out.mesh, options_.min_part_fraction, out.spots_at_iso > 0);
    const std::int64_t wall_voids =
        shell_mode()
            ? wall_voids_euler(out.parts, wall_solid, [&](const Vec3& p) { return placed_.from_mm(p); })
            : 0;
    if (reducing) reduce_output(out, options_, result_.solid.wall_mm, share.part(meshed, reduced));
    // A reduction checked its result already.
    out.topology = out.reduction && out.reduction->topology
                       ? *out.reduction->topology
                       : analyze_topology(out.mesh, share.part(reduced, checked));
    out.pores_from_euler = (result_.unperforated_euler - wall_voids - out.topology.euler_characteristic) / 2;
    check_printable(out.topology, out.iso);
    share.advance(1.0);
  }

  const Input& input_;
  const PreparedInput& prepared_;
  RunMonitor& monitor_;
  const PlacedSurface& placed_;
  Options options_;
  const ZoneOptions zones_;
  const std::chrono::steady_clock::time_point start_;
  std::chrono::steady_clock::time_point mesh_start_;
  PipelineResult result_;
  FeatureZones features_;
  std::optional<Grid> grid_;
  std::function<double(const Vec3&)> grade_field_, mask_;
  std::optional<NarrowBand>
      band_;  // freed before meshing in shell mode, the stage with the largest footprint
  SolveResult solved_;
  std::vector<double> phi_;
  SideTest side_;
  std::optional<ShellSamples> shell_;  // freed once the last level is meshed
  std::vector<std::vector<WallProbe>> probes_;
};

}  // namespace

PreparedInput prepare_input(const Input& input, const Options& given) {
  validate(given);
  const auto start = std::chrono::steady_clock::now();
  PreparedInput prepared;
  prepared.given = given;
  Options& options = prepared.options;
  options = given;
  if (options.preview) options.coarse_start = false;
  // The paper's model where it is not given; holes in mm then set the level and the mean.
  for (auto [value, paper] : {std::pair{&options.alpha, PaperModel::alpha},
                              {&options.epsilon_m, PaperModel::epsilon_m},
                              {&options.dt_h, PaperModel::dt_h},
                              {&options.phi_bar, PaperModel::phi_bar}})
    if (std::isnan(*value)) *value = paper;
  if (options.iso.empty()) options.iso = {PaperModel::iso};
  if (holes_in_mm(options)) {
    prepared.plan = plan_pattern({given.hole_diameter, given.spacing, given.porosity});
    options.voxel_size = choose_voxel_size(options.voxel_size, *prepared.plan);
    // A preview runs on the pattern's own grid, never finer (so no coarse start).
    if (options.preview) options.voxel_size = std::max(options.voxel_size, prepared.plan->voxel_size);
    options.iso = {prepared.plan->level};
    options.phi_bar = prepared.plan->phi_bar;
  }
  prepared.placed = place_surface(input, placement_options(options));
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
  PipelineRun run(input, prepared, monitor);
  run.read_input();
  run.build_band();
  run.solve();
  if (prepared.options.preview) return run.preview();
  run.sample_shell();
  run.mesh();
  run.measure_holes();
  return run.finish();
}

}  // namespace poreshell
