#include "input/placement.hpp"

#include <fmt/format.h>
#include <unistd.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <fstream>
#include <sstream>
#include <string>

#include "band/band.hpp"
#include "core/error.hpp"
#include "core/units.hpp"
#include "geometry/mesh_surface.hpp"
#include "input/point_cloud.hpp"
#include "input/point_segmentation.hpp"
#include "io/mesh_io.hpp"
#include "io/point_io.hpp"

namespace poreshell {
namespace {

// The model sizes poreshell accepts, in mm: a micrometre to a kilometre.
constexpr double kSmallestModelMm = 1e-3, kLargestModelMm = 1e6;

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

// Grid points along the longest side: --resolution, or from --voxel-size over the longest extent.
int resolution_for(const PipelineConfig& c, double longest_extent, int padding_cells) {
  if (!(c.voxel_size > 0.0)) return c.resolution;
  const double voxel_size = c.voxel_size / millimetres_per_unit(c.units);  // in the input's units
  const double n = std::round(longest_extent / voxel_size) + 1 + 2 * padding_cells;
  const std::string points = std::to_string(static_cast<long long>(n));
  if (n > 2048 && !c.holes.empty())  // the hole map chose the voxel size
    throw InputError(
        "holes this small need " + points +
        " grid points along the model's longest side (at most 2048): ask for holes and spacing " +
        std::to_string(n / 2048) + " times larger or more");
  if (n > 2048)
    throw InputError("--voxel-size needs " + points +
                     " grid points along the longest side (at most 2048): choose a larger voxel size");
  if (n < 17 && !c.holes.empty())
    throw InputError(
        "holes this large leave only " + points +
        " grid points along the model's longest side (17 at least): ask for smaller holes and spacing");
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
  if (!(longest > 0.0))
    throw InputError(what +
                     " has zero size: all its points are at one place; give points that sample a surface");
  // Sizes far outside anything printable are a wrong --units or a corrupt file; caught here, before the
  // output's coordinates overflow the STL's floats or collapse to zero.
  const double longest_mm = longest * millimetres_per_unit(c.units);
  if (!(longest_mm <= kLargestModelMm) || !(longest_mm >= kSmallestModelMm))
    throw InputError(
        fmt::format("{} is {:.3g} mm across ({} of the input's coordinates), {} than poreshell "
                    "makes ({:g} mm to {:g} mm); check --units (m, cm, mm, inch) or rescale the model",
                    what, longest_mm, longest, longest_mm > kLargestModelMm ? "larger" : "smaller",
                    kSmallestModelMm, kLargestModelMm));
  placed.resolution = resolution_for(c, longest, kMeshPaddingCells);
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
  Vec3 mean = Vec3::Zero();
  for (const Vec3& p : points) mean += p;
  mean /= static_cast<double>(points.size());
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  for (const Vec3& p : points) covariance += (p - mean) * (p - mean).transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(covariance, Eigen::EigenvaluesOnly);
  const Vec3 spread = solver.eigenvalues();  // ascending
  if (spread[2] > 0.0 && spread[1] <= 1e-12 * spread[2])
    throw InputError(what +
                     " lies on a line: its points sample no surface; give points spread over the surface");
}

// A point cloud: splats (direct) or the paper's densify-and-segment route, on the grid it will get.
void place_points(const PipelineConfig& c, PlacedSurface& placed) {
  PointCloud cloud = read_point_cloud(c.points);
  placed.input.kind = "points";
  placed.input.name = c.points.string();
  placed.input.vertices = static_cast<std::int64_t>(cloud.points.size());
  placed.input.triangles = static_cast<std::int64_t>(cloud.triangles.size());
  placed.input.point_route = c.point_route;
  placed.input.units = c.units;
  placed.input.millimetres_per_unit = millimetres_per_unit(c.units);
  check_not_collinear(cloud.points, "the point cloud '" + c.points.string() + "'");
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

}  // namespace

// The band is counted on a grid 8 times coarser (cheap: 1/64 of the voxels) and scaled by (h_coarse / h)^2,
// since a surface's band grows like its area over h^2.
void check_memory(const PipelineConfig& c, const PlacedSurface& placed, double h_mm) {
  const Surface& surface = *placed.surface;
  const Box& domain = placed.domain;
  const int resolution = placed.resolution;
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
          << (c.max_memory_gb > 0.0 ? "allowed by --max-memory" : "available") << ": ";
  if (c.holes.empty())
    message << "use --resolution " << static_cast<int>(1 + (resolution - 1) * shrink)
            << " or less, or --voxel-size " << h_mm / shrink << " mm or more";
  else  // the voxel size follows the holes: memory grows like (size of the model / spacing)^2
    message << "ask for holes and spacing " << 1.0 / shrink << " times larger or more";
  throw InputError(message.str());
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
    placed.input.units = c.units;
    placed.input.millimetres_per_unit = millimetres_per_unit(c.units);
    if (c.shape_radius > 0.0) {  // in millimetres, centred at the origin
      placed.input.scale = kPaperShapeRadius / c.shape_radius;
      placed.input_center = Vec3::Zero();
    } else {  // the paper's frame: the unit cube
      placed.input_center = Vec3::Constant(0.5);
    }
    placed.resolution = resolution_for(c, 1.0 / placed.input.scale, 0);
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
  placed.input.units = c.units;
  placed.input.millimetres_per_unit = millimetres_per_unit(c.units);
  fit_to_unit_grid(mesh.vertices, c, "the mesh '" + c.mesh.string() + "'", placed);
  placed.surface = std::make_unique<MeshSurface>(mesh);
  placed.mesh = std::move(mesh);
  return placed;
}

}  // namespace poreshell
