// The public API's estimate(): a run's size, cost and sanity before it runs, from the input placed on
// its grid and the band counted on a grid 8 times coarser (band/memory_estimate.hpp). The time and
// output constants are fitted to runs on the development machine (docs/benchmarks.md).

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <variant>

#include "band/band.hpp"
#include "band/memory_estimate.hpp"
#include "core/error.hpp"
#include "core/units.hpp"
#include "geometry/refine.hpp"
#include "input/placement.hpp"
#include "pattern/hole_map.hpp"
#include "pipeline/pipeline.hpp"
#include "pipeline/validate.hpp"
#include "poreshell/poreshell.hpp"
#include "shell/shell.hpp"
#include "solver/solve.hpp"

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
// voxels. (`max_memory_gb` is checked against the cautious 1300 B a voxel of band/memory_estimate.hpp.)
constexpr double kPeakFixedBytes = 50.0 * 1024 * 1024, kPeakBytesPerVoxel = 275.0;
constexpr double kTrianglesPerShellCell = 4.8;  // per band voxel, times (h / shell spacing)^2
// `max_triangles`: the reduction's cost per collapse (two triangles) and its structures per triangle of
// the meshed shell, on top of the run (docs/benchmarks.md "Estimates", 2026-11-27: the CLI reduced
// against unreduced, 2 cores, 5.8-7.6 us a collapse and 169 bytes a triangle on the bunny, 5.9-6.5 us
// and 164 bytes on a sphere r 30 mm).
constexpr double kSecondsPerCollapse = 7.0e-6, kReductionBytesPerTriangle = 170.0;
// The default reduction to `max_deviation` (issue 49): per triangle of the full isosurface, its time and
// its structures, and the share of triangles it keeps. The demo bunny (8 mm holes at 14 mm graded, 2 mm
// wall; 2,100,348 triangles), default against `max_deviation` 0 on a quiet 2-core machine: 6.99 s against
// 3.62 s, 601 against 167 MB peak, 878,818 triangles kept (0.42); the sphere r 50 mm, 6 mm at 10 mm:
// 430,804 of 1,154,928 kept (0.37).
constexpr double kBoundSecondsPerTriangle = 1.6e-6, kBoundBytesPerTriangle = 210.0, kBoundKeptShare = 0.42;
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

// Thresholds of the warnings: the size a print usually has, and a cost worth a second thought.
constexpr double kSmallModelMm = 5.0, kLargeModelMm = 3000.0;
constexpr double kLongRunSeconds = 300.0;
constexpr double kLargeOutputBytes = 300e6;
// The thinnest wall most printers make (resin, fine nozzles); filament needs about twice it.
constexpr double kThinWallMm = 0.4;

// "212 million", "85 thousand", "640": a count as a person reads it.
std::string count_in_words(double n) {
  if (n >= 1e9) return fmt::format("{:.3g} billion", n / 1e9);
  if (n >= 1e6) return fmt::format("{:.3g} million", n / 1e6);
  if (n >= 1e4) return fmt::format("{:.0f} thousand", n / 1e3);
  return fmt::format("{:.0f}", n);
}

void size_warnings(const Estimate& e, const Input& input, const Options& o, std::vector<std::string>& out) {
  const double longest_mm = *std::max_element(e.size_mm.begin(), e.size_mm.end());
  if (longest_mm >= kSmallModelMm && longest_mm <= kLargeModelMm) return;
  std::string text = fmt::format("the model is {} mm across, {} than most prints", readable(longest_mm),
                                 longest_mm < kSmallModelMm ? "smaller" : "larger");
  const Unit unit = std::visit([](const auto& in) { return in.unit; }, input);
  const bool shape_in_mm =
      std::holds_alternative<ShapeInput>(input) && std::get<ShapeInput>(input).radius_mm > 0;
  const double longest_units = longest_mm / (millimetres_per(unit) * o.scale);
  const std::optional<Unit> better = shape_in_mm ? std::nullopt : fitting_unit(longest_units, unit);
  if (better && o.scale == 1.0)
    text += fmt::format("; if its coordinates are in {}, say `units` {} ({} mm)", to_string(*better),
                        to_string(*better), readable(longest_units * millimetres_per(*better)));
  else
    text += fmt::format("; `scale` {:.3g} would make it 100 mm", o.scale * 100.0 / longest_mm);
  out.push_back(text);
}

// A keep-out that misses the model keeps nothing solid: most likely its coordinates are in another frame
// or unit (issue 47: one 460 mm away reported success).
void keep_out_warnings(const Options& o, const PlacedSurface& placed, std::vector<std::string>& out) {
  const Box box = placed.surface->bounds();
  const Vec3 low = placed.to_mm(box.min), high = placed.to_mm(box.max);
  const auto gap = [&](const Vec3& a, const Vec3& b) {  // between the box [a, b] and the model's
    return (low - b).cwiseMax(a - high).cwiseMax(0.0).norm();
  };
  const std::string bounds = fmt::format("({:.4g}, {:.4g}, {:.4g}) to ({:.4g}, {:.4g}, {:.4g})", low.x(),
                                         low.y(), low.z(), high.x(), high.y(), high.z());
  for (const KeepOutSphere& k : o.keep_out) {
    const Vec3 c(k.centre[0], k.centre[1], k.centre[2]);
    if (const double d = gap(c, c) - k.radius; d > 0.0)
      out.push_back(
          fmt::format("`keep_out` {:g},{:g},{:g},{:g} lies {} mm outside the model's bounds {} "
                      "and keeps nothing solid; give it in the input's frame, in mm",
                      c.x(), c.y(), c.z(), k.radius, readable(d), bounds));
  }
  for (const KeepOutBox& k : o.keep_out_boxes) {
    const Vec3 a(k.min[0], k.min[1], k.min[2]), b(k.max[0], k.max[1], k.max[2]);
    if (const double d = gap(a.cwiseMin(b), a.cwiseMax(b)); d > 0.0)
      out.push_back(
          fmt::format("`keep_out_boxes` {:g},{:g},{:g},{:g},{:g},{:g} lies {} mm outside the "
                      "model's bounds {} and keeps nothing solid; give it in the input's frame, in mm",
                      a.x(), a.y(), a.z(), b.x(), b.y(), b.z(), readable(d), bounds));
  }
}

// The estimate from the input as the run will place it.
Estimate estimate_prepared(const Input& input, const PreparedInput& prepared) {
  const Options& given = prepared.given;
  const Options& options = prepared.options;
  const std::optional<PatternPlan>& plan = prepared.plan;
  const PlacedSurface& placed = prepared.placed;
  const double mm_per_grid = placed.mm_per_grid();
  Estimate e;
  const Box box = placed.surface->bounds();
  for (int a = 0; a < 3; ++a)
    e.size_mm[static_cast<std::size_t>(a)] = (box.max[a] - box.min[a]) * mm_per_grid;
  const Grid grid = Grid::fitted(placed.domain, placed.resolution);
  e.grid = grid.dims();
  e.voxel_size_mm = grid.h() * mm_per_grid;
  BandEstimate band = estimate_band(*placed.surface, placed.domain, placed.resolution);
  if (band.voxels == 0.0) {  // a small run: its own band is cheap to count
    band.voxels = static_cast<double>(build_band(*placed.surface, grid).size());
  }
  e.band_voxels = band.voxels;
  e.peak_bytes = kPeakFixedBytes + kPeakBytesPerVoxel * band.voxels;
  const bool shape = placed.input.kind == "shape", points = placed.input.kind == "points";
  if (!plan)
    e.seconds = kSecondsAtReference * std::pow(band.voxels / kReferenceVoxels, kVoxelExponent);
  else if (shape)
    e.seconds = kShapeSecondsFixed + kShapeSecondsPerBandVoxel * band.voxels;
  else if (points)
    e.seconds =
        kPointsSecondsAtReference * std::pow(band.voxels / kPointsReferenceVoxels, kPointsVoxelExponent);
  else
    e.seconds = kMeshSecondsFixed + kMeshSecondsPerBandVoxel * band.voxels;
  // As the pipeline takes it (issue 51): asked, else 2 mm for holes asked in mm, else the band's width.
  const double wall_mm = options.mode == Mode::shell && options.wall > 0.0 ? options.wall
                         : options.mode == Mode::shell && plan
                             ? kDefaultWallMm
                             : 2.0 * BandOptions{}.delta_in_h * e.voxel_size_mm;
  const double shell_mm = options.mode == Mode::shell
                              ? std::min(e.voxel_size_mm, wall_mm / kMinCellsAcrossWall)
                              : e.voxel_size_mm;
  e.triangles = kTrianglesPerShellCell * band.voxels * std::pow(e.voxel_size_mm / shell_mm, 2);
  // A wall thinner than printers make is meshed at a third of it: say both before the run (issue 47:
  // `wall` 0.2 was estimated at 212 million triangles without a word).
  if (options.mode == Mode::shell && options.wall > 0.0 && options.wall < kThinWallMm && !options.preview)
    e.warnings.push_back(
        fmt::format("a `wall` of {:.2g} mm is thinner than most printers make ({:.2g} mm and "
                    "up), and is meshed at {:.2g} mm: about {} triangles; ask for a "
                    "thicker `wall`",
                    options.wall, kThinWallMm, shell_mm, count_in_words(e.triangles)));
  if (const auto target = static_cast<double>(options.max_triangles);
      !options.preview && target > 0 && e.triangles > target) {
    e.seconds += kSecondsPerCollapse * 0.5 * (e.triangles - target);
    e.peak_bytes += kReductionBytesPerTriangle * e.triangles;
    e.triangles = target;
  } else if (!options.preview && reduction_bound(options, wall_mm) > 0.0) {
    e.seconds += kBoundSecondsPerTriangle * e.triangles;
    e.peak_bytes += kBoundBytesPerTriangle * e.triangles;
    e.triangles *= kBoundKeptShare;
  }
  e.stl_bytes = kStlHeaderBytes + kStlBytesPerTriangle * e.triangles;
  if (options.preview) {
    e.preview = true;
    if (builds_surface_layer(options, placed)) {
      e.band_voxels = band.voxels / BandOptions{}.delta_in_h;
      e.seconds = kLayerSecondsFixed + kLayerSecondsPerVoxel * e.band_voxels;
      e.peak_bytes = kLayerPeakFixedBytes + kLayerPeakBytesPerVoxel * e.band_voxels;
    } else if (resolve_layout(options, plan.has_value()) != Layout::cvt) {
      e.seconds = kSolvedPreviewSecondsFixed + kSolvedPreviewSecondsPerVoxel * band.voxels;
    } else {
      e.seconds = shape ? kShapePreviewSecondsFixed + kShapePreviewSecondsPerVoxel * band.voxels
                        : kPointsPreviewSecondsFixed + kPointsPreviewSecondsPerVoxel * band.voxels;
    }
    e.triangles = placed.mesh
                      ? static_cast<double>(preview_surface_mesh(*placed.mesh, grid.h()).triangles.size())
                      : kPreviewTrianglesPerVoxel * band.voxels;
    e.stl_bytes = kStlHeaderBytes + kStlBytesPerTriangle * e.triangles;
    e.ply_bytes = kPlyBytesPerTriangle * e.triangles;
  }

  size_warnings(e, input, given, e.warnings);
  // The smallest extent that holes can span: a flat part's thickness (under a tenth of its length) is
  // not one.
  const double longest_mm = *std::max_element(e.size_mm.begin(), e.size_mm.end());
  double smallest_mm = longest_mm;
  for (const double extent : e.size_mm)
    if (extent >= 0.1 * longest_mm) smallest_mm = std::min(smallest_mm, extent);
  const double hole = plan ? plan->diameter : 0.0;
  if (hole > smallest_mm / 3.0)
    e.warnings.push_back(
        fmt::format("holes of {} mm are more than a third of the model's smallest extent ({} mm): few holes "
                    "fit; ask for a smaller `hole_diameter`",
                    readable(hole), readable(smallest_mm)));
  keep_out_warnings(given, placed, e.warnings);
  if (e.seconds > kLongRunSeconds)
    e.warnings.push_back(
        fmt::format("this run may take about {:.0f} minutes; a coarser `resolution` or "
                    "`voxel_size`, or larger holes, make it faster",
                    e.seconds / 60.0));
  if (e.stl_bytes > kLargeOutputBytes && !e.preview)
    e.warnings.push_back(fmt::format("the output may be about {:.0f} MB as STL; `max_triangles` reduces it",
                                     e.stl_bytes / 1e6));
  return e;
}

}  // namespace

Estimate estimate(const Input& input, const Options& options) {
  return estimate_prepared(input, prepare_input(input, options));
}

Estimate estimate(const Prepared& prepared) {
  if (!prepared.input || !prepared.state)
    throw Error(ErrorCode::invalid_option, "estimate: the Prepared was not made by prepare()");
  return estimate_prepared(*prepared.input, *prepared.state);
}

}  // namespace poreshell
