#pragma once
// Where the input sits on the grid: the surface scaled into the paper's frame (the grid's longest side
// has length 1, h = 1/(N - 1), so the paper's alpha, eps_m and dt = K h mean the same for any model),
// the grid's resolution (--resolution or --voxel-size), and the check that the run fits in memory.

#include <memory>
#include <optional>

#include "geometry/mesh.hpp"
#include "geometry/surface.hpp"
#include "pipeline/pipeline.hpp"

namespace poreshell {

// Grid cells between a mesh's bounding box and the grid's edge: the band (delta = 1.9 h) and its ghosts
// (one more cell) must stay inside the grid.
constexpr int kMeshPaddingCells = 4;

// The surface in grid coordinates; `to_mm` maps results back to millimetres.
struct PlacedSurface {
  std::unique_ptr<Surface> surface;
  Box domain;
  InputSummary input;
  Vec3 input_center = Vec3::Zero();  // x_input = (x_grid - 0.5) / scale + input_center
  int resolution = 0;                // grid points along the longest side
  std::optional<TriangleMesh> mesh;  // a mesh input in grid coordinates: the shell's inside/outside test

  // Millimetres per grid unit, and points from the grid's frame to millimetres and back.
  double mm_per_grid() const { return input.millimetres_per_unit / input.scale; }
  Vec3 to_mm(const Vec3& x) const {
    return ((x - Vec3::Constant(0.5)) / input.scale + input_center) * input.millimetres_per_unit;
  }
  Vec3 from_mm(const Vec3& x) const {
    return (x / input.millimetres_per_unit - input_center) * input.scale + Vec3::Constant(0.5);
  }
};

// Reads or makes the surface and places it on the grid it will get. Throws InputError for bad input.
PlacedSurface place_surface(const PipelineConfig& c);

// Refuses, before anything large is allocated, a run whose band would not fit in memory (throws
// InputError naming the resolution and voxel size that would).
void check_memory(const PipelineConfig& c, const PlacedSurface& placed, double h_mm);

}  // namespace poreshell
