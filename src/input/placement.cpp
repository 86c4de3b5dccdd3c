#include "input/placement.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <string>
#include <type_traits>
#include <variant>

#include "core/error.hpp"
#include "core/units.hpp"
#include "geometry/mesh_clean.hpp"
#include "geometry/mesh_surface.hpp"
#include "geometry/plane_fit.hpp"
#include "input/point_cloud.hpp"
#include "input/point_segmentation.hpp"

namespace poreshell {
namespace {

// The model sizes poreshell accepts, in mm: a micrometre to a kilometre.
constexpr double kSmallestModelMm = 1e-3, kLargestModelMm = 1e6;

// Grid points along the longest side: `resolution`, or from `voxel_size` over the longest extent.
int resolution_for(const PlacementOptions& c, double mm_per_unit, double longest_extent, int padding_cells) {
  if (!(c.voxel_size > 0.0)) return c.resolution;
  const double voxel_size = c.voxel_size / mm_per_unit;  // in the input's units
  const double n = std::round(longest_extent / voxel_size) + 1 + 2 * padding_cells;
  const std::string points = std::to_string(static_cast<long long>(n));
  if (n > 2048 && c.holes_in_mm)  // the hole map chose the voxel size
    throw OptionError("hole_diameter",
                      "holes this small need " + points +
                          " grid points along the model's longest side (at most 2048): ask for holes and "
                          "spacing " +
                          fmt::format("{:g}", std::ceil(10.0 * n / 2048) / 10.0) + " times larger or more");
  if (n > 2048)
    throw OptionError("voxel_size", "`voxel_size` needs " + points +
                                        " grid points along the longest side (at most 2048): choose a larger "
                                        "voxel size");
  if (n < 17 && c.holes_in_mm)
    throw OptionError("hole_diameter",
                      "holes this large leave only " + points +
                          " grid points along the model's longest side (17 at least): ask for smaller holes "
                          "and spacing");
  if (n < 17)
    throw OptionError("voxel_size", "`voxel_size` is too coarse for this model: choose a smaller voxel size");
  return static_cast<int>(n);
}

// Scales and centres `vertices` (a mesh's or a point cloud's) into the paper's frame, with padding, and
// sets the placement's resolution, scale, centre and domain.
// Holes as large as the model's smallest extent (a flat part's thickness, under a tenth of its length,
// is not one) fit nowhere: refused before the run rather than giving no holes, with the unit that would
// make the model a print's size, if one does (issue 47: the bunny's metres read as millimetres were told
// to ask for smaller holes).
void check_holes_fit(const PlacementOptions& c, const Vec3& extent_mm, double mm_per_unit, Unit unit,
                     const std::string& what) {
  const double hole = c.hole_diameter > 0.0 ? c.hole_diameter : c.spacing;
  if (!(hole > 0.0)) return;
  const double longest = extent_mm.maxCoeff();
  double smallest = longest;
  for (int a = 0; a < 3; ++a)
    if (extent_mm[a] >= 0.1 * longest) smallest = std::min(smallest, extent_mm[a]);
  if (hole < smallest) return;
  const char* asked = c.hole_diameter > 0.0 ? "holes" : "a spacing";
  std::string text = fmt::format("{} is {} mm across at its narrowest, and {} of {} mm fit nowhere on it",
                                 what, readable(smallest), asked, readable(hole));
  const double longest_units = longest / mm_per_unit;
  const std::optional<Unit> better = c.scale == 1.0 ? fitting_unit(longest_units, unit) : std::nullopt;
  if (better)
    text += fmt::format("; if its coordinates are in {}, say `units` {} (it is then {} mm across)",
                        to_string(*better), to_string(*better),
                        readable(longest_units * millimetres_per(*better)));
  text += fmt::format("; {}ask for `{}` well under {} mm", better ? "else " : "",
                      c.hole_diameter > 0.0 ? "hole_diameter" : "spacing", readable(smallest));
  throw OptionError(c.hole_diameter > 0.0 ? "hole_diameter" : "spacing", text);
}

void fit_to_unit_grid(std::vector<Vec3>& vertices, const PlacementOptions& c, const std::string& what,
                      Unit unit, PlacedSurface& placed) {
  if (vertices.empty()) throw InputError(what + " has no vertices");
  Box box{vertices.front(), vertices.front()};
  for (const Vec3& v : vertices) {
    box.min = box.min.cwiseMin(v);
    box.max = box.max.cwiseMax(v);
  }
  const double longest = (box.max - box.min).maxCoeff();
  if (!(longest > 0.0))
    throw InputError(what +
                     " has zero size: all its points are at one place; give points that sample a surface");
  // Sizes far outside anything printable are a wrong unit or a corrupt file; caught here, before the
  // output's coordinates overflow the STL's floats or collapse to zero.
  const double longest_mm = longest * placed.input.millimetres_per_unit;
  if (!(longest_mm <= kLargestModelMm) || !(longest_mm >= kSmallestModelMm))
    throw InputError(
        fmt::format("{} is {:.3g} mm across ({} of the input's coordinates), {} than poreshell "
                    "makes ({:g} mm to {:g} mm); check `units` (m, cm, mm, inch) or rescale the model",
                    what, longest_mm, longest, longest_mm > kLargestModelMm ? "larger" : "smaller",
                    kSmallestModelMm, kLargestModelMm));
  check_holes_fit(c, (box.max - box.min) * placed.input.millimetres_per_unit,
                  placed.input.millimetres_per_unit, unit, what);
  placed.resolution = resolution_for(c, placed.input.millimetres_per_unit, longest, kMeshPaddingCells);
  const double h = 1.0 / (placed.resolution - 1);
  const double scale = (1.0 - 2 * kMeshPaddingCells * h) / longest;
  placed.input.scale = scale;
  placed.input_center = 0.5 * (box.min + box.max);
  for (Vec3& v : vertices) v = (v - placed.input_center) * scale + Vec3::Constant(0.5);
  const Vec3 half = 0.5 * scale * (box.max - box.min) + Vec3::Constant(kMeshPaddingCells * h);
  placed.domain = Box{Vec3::Constant(0.5) - half, Vec3::Constant(0.5) + half};
}

// Points on one line sample no surface: the variance across the line is round-off (10^-12) next to
// the variance along it.
void check_not_collinear(const std::vector<Vec3>& points, const std::string& what) {
  if (points.size() < 2) return;
  const Vec3 spread = fit_plane(points).variances;  // ascending
  if (spread[2] > 0.0 && spread[1] <= 1e-12 * spread[2])
    throw InputError(what +
                     " lies on a line: its points sample no surface; give points spread over the surface");
}

// A point cloud: splats (direct) or the paper's densify-and-segment route, on the grid it will get.
void place_points(const PointsInput& in, const PlacementOptions& c, PlacedSurface& placed) {
  std::vector<Vec3> points(in.points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    points[i] = Vec3(in.points[i][0], in.points[i][1], in.points[i][2]);
    if (!points[i].allFinite())
      throw InputError("point " + std::to_string(i) + " of '" + in.name +
                       "' has a NaN or infinite coordinate: remove it or fix the file");
  }
  for (const Triangle& t : in.patches)
    for (std::int32_t v : t)
      if (v < 0 || static_cast<std::size_t>(v) >= points.size())
        throw InputError("a patch of '" + in.name + "' refers to point " + std::to_string(v) + " of " +
                         std::to_string(points.size()));
  std::vector<std::array<std::int32_t, 3>> patches(in.patches.begin(), in.patches.end());
  placed.input.kind = "points";
  placed.input.name = in.name;
  placed.input.vertices = static_cast<std::int64_t>(points.size());
  placed.input.triangles = static_cast<std::int64_t>(patches.size());
  placed.input.point_route = c.point_route == PointRoute::direct ? "direct" : "paper";
  placed.input.units = to_string(in.unit);
  placed.input.millimetres_per_unit = millimetres_per(in.unit) * c.scale;
  check_not_collinear(points, "the point cloud '" + in.name + "'");
  fit_to_unit_grid(points, c, "the point cloud '" + in.name + "'", in.unit, placed);
  if (c.point_route == PointRoute::direct) {
    placed.surface = std::make_unique<SplatSurface>(std::move(points));
    return;
  }
  SegmentationStats stats;
  placed.surface =
      segment_point_cloud(points, patches, Grid::fitted(placed.domain, placed.resolution), {}, &stats);
  placed.input.densified_points = stats.points;
  placed.input.segmentation_iterations = stats.iterations;
}

void place_shape(const ShapeInput& in, const PlacementOptions& c, PlacedSurface& placed) {
  const std::string name = in.kind == ShapeKind::torus ? "torus" : "sphere";
  if (!(in.radius_mm >= 0.0) || !std::isfinite(in.radius_mm))
    throw OptionError("radius_mm", "`radius_mm` must be a positive length in millimetres");
  if (in.radius_mm > 0.0 && in.unit != Unit::mm)
    throw OptionError("units",
                      "`units` names the unit of an input file: a shape with a radius is in mm already");
  placed.surface = make_paper_shape(name);
  placed.domain = Box{Vec3::Zero(), Vec3::Ones()};
  placed.input.kind = "shape";
  placed.input.name = name;
  placed.input.euler_characteristic = in.kind == ShapeKind::torus ? 0 : 2;
  placed.input.units = to_string(in.unit);
  placed.input.millimetres_per_unit = millimetres_per(in.unit) * c.scale;
  if (in.radius_mm > 0.0) {  // in millimetres, centred at the origin
    placed.input.scale = kPaperShapeRadius / in.radius_mm;
    placed.input_center = Vec3::Zero();
  } else {  // the paper's frame: the unit cube
    placed.input_center = Vec3::Constant(0.5);
  }
  placed.resolution = resolution_for(c, placed.input.millimetres_per_unit, 1.0 / placed.input.scale, 0);
}

void place_mesh(const MeshInput& in, const PlacementOptions& c, PlacedSurface& placed) {
  TriangleMesh mesh = to_triangle_mesh(in.mesh);
  const MeshInputStats stats = clean_triangle_mesh(mesh);
  placed.input = {"mesh",
                  in.name,
                  stats.vertices,
                  stats.triangles,
                  stats.boundary_edges,
                  in.dropped_degenerate + stats.dropped_degenerate,
                  analyze_topology(mesh).euler_characteristic,
                  1.0};
  placed.input.dropped_duplicate = in.dropped_duplicate + stats.dropped_duplicate;
  placed.input.units = to_string(in.unit);
  placed.input.millimetres_per_unit = millimetres_per(in.unit) * c.scale;
  fit_to_unit_grid(mesh.vertices, c, "the mesh '" + in.name + "'", in.unit, placed);
  placed.surface = std::make_unique<MeshSurface>(mesh);
  placed.mesh = std::move(mesh);
}

}  // namespace

TriangleMesh to_triangle_mesh(const Mesh& mesh) {
  TriangleMesh out;
  out.vertices.reserve(mesh.vertices.size());
  for (const Point& p : mesh.vertices) out.vertices.emplace_back(p[0], p[1], p[2]);
  out.triangles.assign(mesh.triangles.begin(), mesh.triangles.end());
  return out;
}

PlacedSurface place_surface(const Input& input, const PlacementOptions& options) {
  PlacedSurface placed;
  std::visit(
      [&](const auto& in) {
        using T = std::decay_t<decltype(in)>;
        if constexpr (std::is_same_v<T, ShapeInput>)
          place_shape(in, options, placed);
        else if constexpr (std::is_same_v<T, MeshInput>)
          place_mesh(in, options, placed);
        else
          place_points(in, options, placed);
      },
      input);
  return placed;
}

}  // namespace poreshell
