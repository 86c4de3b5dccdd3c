#include "pipeline/run_cost.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>

#include "band/memory_estimate.hpp"
#include "core/error.hpp"
#include "geometry/refine.hpp"
#include "pipeline/solve_stage.hpp"
#include "pipeline/validate.hpp"
#include "reduce/mesh_decimate.hpp"
#include "shell/shell.hpp"

namespace poreshell {
namespace {

// docs/benchmarks.md, "Estimates": fits to the CLI's wall times (2 threads, quiet hours). With epsilon
// tied to h (no hole size asked) the pores shrink with the voxels and the steps grow: t = 3.5 s (V /
// 133k)^1.78 through the bunny at 131 and 260 points. With holes in mm the equation starts from the even
// layout and takes some 20-40 steps whatever the grid, so the time follows the band: t = 0.1 s + 10.5 us V
// for the analytic shapes, 0.3 s + 21 us V for meshes (closest points on the mesh for every band voxel and
// shell sample), and 21.3 s (V / 644k)^1.41 for point clouds (the surface made from the points).
constexpr double kSecondsAtReference = 3.5, kReferenceVoxels = 133356.0, kVoxelExponent = 1.78;
constexpr double kShapeSecondsFixed = 0.1, kShapeSecondsPerBandVoxel = 10.5e-6;
constexpr double kMeshSecondsFixed = 0.3, kMeshSecondsPerBandVoxel = 21e-6;
constexpr double kPointsSecondsAtReference = 21.3, kPointsReferenceVoxels = 644e3,
                 kPointsVoxelExponent = 1.41;
// Peak resident memory of the bunny series at bc095dd: 89, 183, 659 and 1656 MiB at 133k-6.05M band
// voxels.
constexpr double kPeakFixedBytes = 50.0 * 1024 * 1024, kPeakBytesPerVoxel = 275.0;
// A mesh input's own structures (the triangles, their search tree, the features' and the trim line's
// tables) and the time to build them, per input triangle: the bunny's full 2,100,348-triangle shell taken
// as input with 8 mm holes at 14 mm (2 threads, 2026-11-29) peaked at 1,186 MiB and took 15.4 s, against
// 590 MiB and 8.4 s for the 69,451-triangle scan on the same request: 300 B and 3.4 us a triangle.
constexpr double kInputBytesPerTriangle = 300.0, kInputSecondsPerTriangle = 3.4e-6;
constexpr double kTrianglesPerShellCell = 4.8;  // per band voxel, times (h / shell spacing)^2
// `max_triangles`: the reduction's cost per collapse (two triangles) and its structures per triangle of
// the meshed shell, on top of the run (docs/benchmarks.md "Estimates", 2026-11-27: the CLI reduced
// against unreduced, 2 cores, 169 bytes a triangle on the bunny, 164 on a sphere r 30 mm). Its placed
// collapses (issue 49, 2026-11-29, the same way): the bunny 6 mm at 10 mm to 250,000 at 0.05 mm 26.2 s
// against 5.75 s, 22 us a collapse; the sphere r 30 mm to 60,000 4.09 s against 0.54 s, 21 us.
constexpr double kSecondsPerCollapse = 21.0e-6, kReductionBytesPerTriangle = 170.0;
// The default reduction to `max_deviation` (issue 49): per triangle of the full isosurface, its time and
// its structures, and the share of triangles it keeps. The demo bunny (8 mm holes at 14 mm graded, 2 mm
// wall; 2,100,348 triangles), default against `max_deviation` 0 on a quiet 2-core machine: 6.99 s against
// 3.62 s, 601 against 167 MB peak. Kept since the isosurface's clamped crossings lie on the surface
// (bench/lean-mesh, 2026-12-07): the bunny 723,644 of 2,100,938 (0.34), the sphere r 50 mm, 6 mm at
// 10 mm, 338,644 of 1,154,928 (0.29); the estimate takes the larger, rounded up.
constexpr double kBoundSecondsPerTriangle = 1.6e-6, kBoundBytesPerTriangle = 210.0, kBoundKeptShare = 0.35;
// `lean`: the placed collapses keep 0.18 (the bunny: 375,752) and 0.18 (the sphere: 202,122), in about the
// fan bounds' memory (bench_reduce: 731 against 703 MB, 405 against 404 MB).
constexpr double kPlacedKeptShare = 0.18;
constexpr double kStlBytesPerTriangle = 50.0;
constexpr double kStlHeaderBytes = 84.0;
// A preview: a mesh input split as the pipeline splits it (counted, not guessed); other inputs as the
// band's slab {|psi| < h} meshed on the band's grid, about 4.8 triangles per band voxel (the bunny's
// points, 8 mm holes at 14 mm: 790,948 from 163,539). Written as PLY with a colour per vertex (12 + 3
// bytes a vertex, 13 a triangle, half as many vertices as triangles: 20.5 bytes a triangle).
// Its time, linear in the band (the CLI's wall time, 2 threads, docs/benchmarks.md "Estimates"): from the
// even layout (no solve) 0.02 s + 3.0 us V for the shapes (spheres of 25-100 mm) and 0.2 s + 5.3 us V for
// point clouds (the bunny's points, 8 / 14, 6 / 10 and 4 / 7 mm); a preview that runs the equation
// (`layout` paper) 0.8 s + 8.4 us V, the older fit through bunny previews of 0.16, 0.38 and 1.26 M band
// voxels, not measured again.
constexpr double kPreviewTrianglesPerVoxel = 4.84, kPlyBytesPerTriangle = 20.5;
constexpr double kShapePreviewSecondsFixed = 0.02, kShapePreviewSecondsPerVoxel = 3.0e-6;
constexpr double kPointsPreviewSecondsFixed = 0.2, kPointsPreviewSecondsPerVoxel = 5.3e-6;
constexpr double kSolvedPreviewSecondsFixed = 0.8, kSolvedPreviewSecondsPerVoxel = 8.4e-6;
// A mesh's preview builds only the band's surface layer, {|psi| < h} of {|psi| < delta}: h / delta of the
// band (the bunny at 8 / 14, 5 / 9 and 3 / 5 mm: 0.528-0.538 of its band, 0.538-0.553 of the band
// estimated). Time and peak memory per layer voxel, fitted through the CLI's wall time and peak RSS of
// those three (2 threads, 2026-11-26): 0.82-0.86, 1.84-1.96 and 5.94-6.14 s; 46, 72 and 179 MiB.
constexpr double kLayerSecondsFixed = 0.11, kLayerSecondsPerVoxel = 8.9e-6;
constexpr double kLayerPeakFixedBytes = 26.0 * 1024 * 1024, kLayerPeakBytesPerVoxel = 240.0;

// The preview's figures in place of the shell's.
void preview_cost(const PreparedInput& prepared, const Grid& grid, bool count_triangles, RunCost& c) {
  const Options& options = prepared.options;
  const PlacedSurface& placed = prepared.placed;
  const double band = c.band_voxels;
  if (builds_surface_layer(options, placed)) {
    c.band_voxels = band / BandOptions{}.delta_in_h;
    c.seconds = kLayerSecondsFixed + kLayerSecondsPerVoxel * c.band_voxels;
    c.peak_bytes = kLayerPeakFixedBytes + kLayerPeakBytesPerVoxel * c.band_voxels;
  } else if (resolve_layout(options, prepared.plan.has_value()) != Layout::cvt) {
    c.seconds = kSolvedPreviewSecondsFixed + kSolvedPreviewSecondsPerVoxel * band;
  } else {
    c.seconds = placed.input.kind == "shape"
                    ? kShapePreviewSecondsFixed + kShapePreviewSecondsPerVoxel * band
                    : kPointsPreviewSecondsFixed + kPointsPreviewSecondsPerVoxel * band;
  }
  if (!count_triangles) return;  // splitting a mesh to count its triangles takes a while
  c.triangles = placed.mesh
                    ? static_cast<double>(preview_surface_mesh(*placed.mesh, grid.h()).triangles.size())
                    : kPreviewTrianglesPerVoxel * band;
  c.stl_bytes = kStlHeaderBytes + kStlBytesPerTriangle * c.triangles;
  c.ply_bytes = kPlyBytesPerTriangle * c.triangles;
}

}  // namespace

WallChoice choose_wall(const Options& options, bool asked_in_mm, double voxel_size_mm) {
  const bool shell = options.mode == Mode::shell;
  if (shell && options.wall > 0.0) return {options.wall, "asked"};
  if (shell && asked_in_mm) return {kDefaultWallMm, "default"};
  return {2.0 * BandOptions{}.delta_in_h * voxel_size_mm, "band"};
}

RunCost estimate_run_cost(const PreparedInput& prepared, bool for_printout) {
  const Options& options = prepared.options;
  const PlacedSurface& placed = prepared.placed;
  const Grid grid = Grid::fitted(placed.domain, placed.resolution);
  RunCost c;
  c.voxel_size_mm = grid.h() * placed.mm_per_grid();
  c.band_voxels = estimate_band_voxels(*placed.surface, placed.domain, placed.resolution);
  if (c.band_voxels == 0.0) {
    if (!for_printout) return c;
    c.band_voxels = static_cast<double>(build_band(*placed.surface, grid).size());
  }
  const double band = c.band_voxels;
  const double input_triangles = placed.mesh ? static_cast<double>(placed.input.triangles) : 0.0;
  c.fixed_bytes = kPeakFixedBytes + kInputBytesPerTriangle * input_triangles;
  c.peak_bytes = c.fixed_bytes + kPeakBytesPerVoxel * band;
  const std::string& kind = placed.input.kind;
  if (!prepared.plan)
    c.seconds = kSecondsAtReference * std::pow(band / kReferenceVoxels, kVoxelExponent);
  else if (kind == "shape")
    c.seconds = kShapeSecondsFixed + kShapeSecondsPerBandVoxel * band;
  else if (kind == "points")
    c.seconds = kPointsSecondsAtReference * std::pow(band / kPointsReferenceVoxels, kPointsVoxelExponent);
  else
    c.seconds = kMeshSecondsFixed + kMeshSecondsPerBandVoxel * band;
  c.seconds += kInputSecondsPerTriangle * input_triangles;
  const bool shell = options.mode == Mode::shell;
  const double wall_mm = choose_wall(options, prepared.plan.has_value(), c.voxel_size_mm).mm;
  c.shell_mm = shell ? std::min(c.voxel_size_mm, wall_mm / kMinCellsAcrossWall) : c.voxel_size_mm;
  c.triangles = kTrianglesPerShellCell * band * std::pow(c.voxel_size_mm / c.shell_mm, 2);
  if (options.preview) {
    preview_cost(prepared, grid, for_printout, c);
    return c;
  }
  const auto target = static_cast<double>(options.max_triangles);
  if (target > 0 && c.triangles > target && target >= kBoundsFirstShare * c.triangles) {
    // A budget the fans' bounds reach (mesh_decimate.hpp): their cost.
    c.seconds += kBoundSecondsPerTriangle * c.triangles;
    c.peak_bytes += kBoundBytesPerTriangle * c.triangles;
    c.triangles = target;
  } else if (target > 0 && c.triangles > target) {
    c.seconds += kSecondsPerCollapse * 0.5 * (c.triangles - target);
    c.peak_bytes += kReductionBytesPerTriangle * c.triangles;
    c.triangles = target;
  } else if (reduction_bound(options, wall_mm) > 0.0 && options.lean) {
    c.seconds += kSecondsPerCollapse * 0.5 * (1.0 - kPlacedKeptShare) * c.triangles;
    c.peak_bytes += kBoundBytesPerTriangle * c.triangles;
    c.triangles *= kPlacedKeptShare;
  } else if (reduction_bound(options, wall_mm) > 0.0) {
    c.seconds += kBoundSecondsPerTriangle * c.triangles;
    c.peak_bytes += kBoundBytesPerTriangle * c.triangles;
    c.triangles *= kBoundKeptShare;
  }
  c.stl_bytes = kStlHeaderBytes + kStlBytesPerTriangle * c.triangles;
  return c;
}

void check_run_fits(const RunCost& cost, const PreparedInput& prepared) {
  const Options& options = prepared.options;
  const MemoryLimit limit = memory_limit(options.max_memory_gb);
  if (cost.peak_bytes <= limit.bytes) return;
  constexpr double kMiB = 1024.0 * 1024.0;
  const std::string allowed = options.max_memory_gb > 0.0
                                  ? fmt::format("{:.3g} GB {}", options.max_memory_gb, limit.source)
                                  : fmt::format("{:.0f} MiB {}", limit.bytes / kMiB, limit.source);
  std::string message = fmt::format(
      "this run needs about {:.0f} MiB (about {:.3g} million band voxels at h = {:.3g} mm), more than the "
      "{}: ",
      cost.peak_bytes / kMiB, cost.band_voxels / 1e6, cost.voxel_size_mm, allowed);
  // What the grid changes shrinks with the square of its spacing; the program and the input do not.
  const double room = limit.bytes - cost.fixed_bytes;
  const double shrink = room > 0.0 ? std::sqrt(room / (cost.peak_bytes - cost.fixed_bytes)) : 0.0;
  if (shrink == 0.0)
    message += fmt::format(
        "the program and the input alone need about {:.0f} MiB; simplify the input or "
        "free memory",
        cost.fixed_bytes / kMiB);
  else if (!holes_in_mm(prepared.given))
    message += fmt::format("use `resolution` {} or less, or `voxel_size` {:.3g} mm or more",
                           static_cast<int>(1 + (prepared.placed.resolution - 1) * shrink),
                           cost.voxel_size_mm / shrink * 1.01);
  else  // the voxel size follows the holes: memory grows like (size of the model / spacing)^2
    message += fmt::format("ask for holes and spacing {:.3g} times larger or more", 1.01 / shrink);
  throw Error(ErrorCode::too_large, message, options.max_memory_gb > 0.0 ? "max_memory_gb" : "");
}

}  // namespace poreshell
