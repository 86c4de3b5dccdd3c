#pragma once
// Where the input sits on the grid: the surface scaled into the paper's frame (the grid's longest side
// has length 1, h = 1/(N - 1), so the paper's alpha, eps_m and dt = K h mean the same for any model)
// and the grid's resolution (`resolution` or `voxel_size`).

#include <memory>
#include <optional>
#include <string>

#include "geometry/mesh.hpp"
#include "geometry/surface.hpp"
#include "poreshell/geometry.hpp"
#include "poreshell/options.hpp"

namespace poreshell {

// Grid cells between a mesh's bounding box and the grid's edge: the band (delta = 1.9 h) and its ghosts
// (one more cell) must stay inside the grid.
constexpr int kMeshPaddingCells = 4;

struct InputSummary {
  std::string kind;  // "shape", "mesh" or "points"
  std::string name;  // shape name, file path or the caller's name
  std::int64_t vertices = 0, triangles = 0, boundary_edges = 0, dropped_degenerate = 0;
  std::int64_t euler_characteristic = 2;  // of the surface; the unperforated shell has twice this
  double scale = 1.0;                     // grid units per input unit (meshes are fitted to the unit box)
  std::string units = "mm";               // unit of the input's coordinates
  double millimetres_per_unit = 1.0;
  std::string point_route{};                         // points: "direct" or "paper"
  std::int64_t densified_points = 0;                 // points, paper route: after Fig. 8's densification
  int segmentation_iterations = 0;                   // points, paper route: explicit steps of eq. (3.3)
  std::int64_t thin_vertices = 0, crease_edges = 0;  // features kept solid (input/features.hpp)
  std::int64_t dropped_duplicate = 0;                // repeats of a triangle (io/mesh_io.hpp)
};

// The surface in grid coordinates; `to_mm` maps results back to millimetres.
struct PlacedSurface {
  std::unique_ptr<Surface> surface;
  Box domain;
  InputSummary input;
  Vec3 input_center = Vec3::Zero();  // x_input = (x_grid - 0.5) / scale + input_center
  int resolution = 0;                // grid points along the longest side
  std::optional<TriangleMesh> mesh;  // a mesh input in grid coordinates: the shell's inside/outside test

  // The mesh input where it has an open boundary (where the wall ends at a trim line), else null.
  const TriangleMesh* open_mesh() const { return mesh && input.boundary_edges > 0 ? &*mesh : nullptr; }

  // Millimetres per grid unit, and points from the grid's frame to millimetres and back.
  double mm_per_grid() const { return input.millimetres_per_unit / input.scale; }
  Vec3 to_mm(const Vec3& x) const {
    return ((x - Vec3::Constant(0.5)) / input.scale + input_center) * input.millimetres_per_unit;
  }
  Vec3 from_mm(const Vec3& x) const {
    return (x / input.millimetres_per_unit - input_center) * input.scale + Vec3::Constant(0.5);
  }
};

// What placing the input is asked for: the request's share for it, filled by placement_options()
// (pipeline/stage_options.hpp); no defaults of its own, so that Options' are the only ones.
struct PlacementOptions {
  int resolution{};     // grid points along the longest side, where voxel_size is 0
  double voxel_size{};  // mm (the hole map's, for holes in mm)
  double scale{};       // the input's coordinates times this, before its unit
  PointRoute point_route{};
  double hole_diameter{}, spacing{};  // mm as asked (0: not), to check that holes fit
  bool holes_in_mm{};                 // the hole map chose voxel_size
};

// Makes the surface of the input and places it on the grid it will get. Throws InputError for input
// that cannot be used, OptionError for a grid the options make impossible.
PlacedSurface place_surface(const Input& input, const PlacementOptions& options);

// A mesh input as the library's mesh: coordinates in its own unit, cleaned (mesh_io.hpp).
TriangleMesh to_triangle_mesh(const Mesh& mesh);

}  // namespace poreshell
