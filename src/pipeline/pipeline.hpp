#pragma once
// The whole job in stage order: surface -> grid -> narrow band -> solver -> narrow volume -> mesh,
// checks -> files. Front ends (the CLI, later bindings) call only this.

#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "band/band.hpp"
#include "geometry/mesh.hpp"
#include "pattern/grading.hpp"
#include "pattern/hole_map.hpp"
#include "pattern/pattern.hpp"
#include "shell/hole_table.hpp"
#include "shell/mesh_decimate.hpp"
#include "shell/wall_measure.hpp"
#include "solver/coarse_start.hpp"
#include "solver/fast_solver.hpp"
#include "solver/model.hpp"
#include "solver/reference_solver.hpp"
#include "solver/time_stepping.hpp"

namespace poreshell {

struct PipelineConfig {
  std::string shape = "sphere";  // sphere | torus (section 3.2, on the unit cube)
  double shape_radius = 0.0;   // mm: the shape at this size (sphere radius, torus major radius); 0: unit cube
  std::filesystem::path mesh;  // a triangle mesh file instead of a shape (STL, OBJ, PLY, OFF, 3MF)
  std::filesystem::path points;  // a point cloud file instead of a shape (XYZ text, PLY vertices)
  int resolution = 131;          // grid points along the longest side (the paper's N)
  double voxel_size = 0.0;       // h in millimetres; when > 0 it sets the resolution instead
  double max_memory_gb = 0.0;    // refuse runs estimated to need more; 0: the memory available now
  double rim_mm = 0.0;           // solid rim of this width along the input mesh's open boundary
  std::vector<std::array<double, 4>> keep_out;        // solid spheres: centre x, y, z and radius, in mm
  std::vector<std::array<double, 6>> keep_out_boxes;  // solid boxes: min x, y, z and max x, y, z, in mm
  std::string keep_out_mask;  // a PLY vertex property of the input mesh: solid where it is 1 (above 0.5)
  std::string units = "mm";   // unit of the input's coordinates: m | cm | mm | inch; outputs are in mm
  double alpha = 1400.0;      // nonlocal strength alpha
  double epsilon_m = 4.0;     // m in epsilon_m = m h / (2 sqrt 2 atanh 0.9)
  double dt_in_h = 100.0;     // time step in units of h
  double tolerance = 1e-3;    // stop when e_c (RMS over the band) < tolerance
  int max_steps = 2000;
  std::uint64_t seed = 1;
  double phi_bar = -0.3;   // mean concentration
  double amplitude = 0.5;  // phi0 = phi_bar + amplitude * rand, rand uniform in [-1, 1]
  std::vector<double> iso_levels{0.0};
  // Hole size asked for (mm): sets alpha, epsilon, phi_bar, the time step, the pore level and, unless
  // voxel_size is given, h (hole_map.hpp). Empty: the paper's parameters above.
  HoleRequest holes;
  std::optional<GradeSpec> grade;  // hole-size grading (needs `holes`)
  std::string solver = "fast";     // fast (docs/solver.md) | reference (the paper's scheme, relaxation)
  InnerOptions inner;              // reference solver
  FastOptions fast;                // fast solver
  // Fast solver: where epsilon spans 1.8 eps_4 or more, form the pattern on the grid where it spans eps_4
  // and carry it here (coarse_start.hpp).
  bool coarse_start = true;
  int energy_every = 0;          // evaluate the energy (3.2) every K steps and at the end; 0: never
  std::filesystem::path output;  // .stl .3mf .obj .ply; with several iso levels OUT-isoC.ext per level
  std::string mode = "shell";    // shell (wall of its own, pores straight through) | narrow-volume (Fig. 3b)
  double wall = 0.0;             // shell wall thickness in mm; 0: the band's width 2 delta = 3.81 h
  std::string offset = "centered";  // shell wall: centered on the surface, inside or outside it
  std::int64_t max_triangles = 0;   // reduce each output to at most this many triangles; 0: as meshed
  double max_deviation = 0.05;      // mm: how far the reduced surface may lie from the meshed one
  std::function<void(const StepProgress&)> on_step;
  std::string point_route = "direct";  // --points: direct (splats, no PDE) | paper (densify + eq. 3.3)
};

struct MeshOutput {
  double iso = 0.0;
  std::filesystem::path path;
  MeshTopology topology;
  HoleStats holes;                          // on the band at this level, lengths in mm
  std::optional<DecimateResult> reduction;  // --max-triangles
  WallMeasurement wall;                     // across the written solid's wall, mm (shell mode)
  std::int64_t spots_at_iso = 0;            // connected components of {phi > iso} on the band
  std::int64_t pores_from_euler = 0;        // (chi of the unperforated solid - chi) / 2
  HoleTable hole_table;                     // each hole measured on the written mesh, mm
};

struct InputSummary {
  std::string kind;  // "shape", "mesh" or "points"
  std::string name;  // shape name or file path
  std::int64_t vertices = 0, triangles = 0, boundary_edges = 0, dropped_degenerate = 0;
  std::int64_t euler_characteristic = 2;  // of the surface; the unperforated shell has twice this
  double scale = 1.0;                     // grid units per input unit (meshes are fitted to the unit box)
  std::string units = "mm";               // unit of the input's coordinates
  double millimetres_per_unit = 1.0;
  std::string point_route{};          // points: "direct" or "paper"
  std::int64_t densified_points = 0;  // points, paper route: after Fig. 8's densification
  int segmentation_iterations = 0;    // points, paper route: explicit steps of eq. (3.3)
};

// The printable solid as built (lengths in mm, the unit of every output).
struct SolidSummary {
  std::string mode;                      // shell | narrow-volume
  double wall_mm = 0.0;                  // requested wall (shell); the band's width 2 delta (narrow volume)
  std::string offset;                    // centered | inside | outside (shell)
  double spacing_mm = 0.0;               // grid spacing the solid was meshed on
  std::size_t samples = 0;               // sparse grid points sampled (shell)
  std::int64_t incomplete_stencils = 0;  // closest points whose 8 band corners were not all present
  double seconds_sample = 0.0;           // distance, closest point, sign and pattern per sample
};

struct PipelineResult {
  InputSummary input;
  std::array<int, 3> grid_dims{};
  double h = 0.0;  // in grid units (the longest side is 1); h / input.scale in the input's units
  std::size_t band_voxels = 0, ghosts = 0;
  BandStats band_stats;
  std::size_t band_bytes = 0;
  ModelParameters model;
  double dt = 0.0;
  HoleRequest requested_holes;            // as given
  std::optional<PatternPlan> plan;        // the hole map's choice, when a hole size was asked for
  std::optional<GradingSummary> grading;  // when graded
  std::string solver_name;
  std::string inner_iteration;
  RunResult run;                            // on this grid
  std::optional<CoarseLevel> coarse_start;  // the run on the pattern's grid before it, if any
  SpotStats spots;                          // at phi > 0
  std::int64_t unperforated_euler = 0;      // chi of the solid without pores
  SolidSummary solid;
  std::vector<MeshOutput> meshes;
  double seconds_input = 0.0, seconds_band = 0.0, seconds_solve = 0.0, seconds_mesh = 0.0,
         seconds_total = 0.0;
  // Peak resident memory of the process at the end of each stage (bytes; 0 where not measurable).
  std::size_t peak_rss_after_band = 0, peak_rss_after_solve = 0, peak_rss_total = 0;
  std::size_t solver_bytes = 0;  // the solver's own arrays (multigrid hierarchy, work vectors)
  int threads = 0;
};

// Output path for one iso level: OUT itself for a single level, OUT-isoC.ext for several.
std::filesystem::path output_path_for_level(const std::filesystem::path& output, double iso, bool several);

// The narrow volume of Fig. 3(b): phi on the band, 1 on the ghosts and everywhere else; the solid is
// {phi < iso}. Returns its isosurface.
TriangleMesh narrow_volume_mesh(const NarrowBand& band, std::span<const double> phi, double iso);
// Its Euler characteristic, without making it.
std::int64_t narrow_volume_euler(const NarrowBand& band, std::span<const double> phi, double iso);

PipelineResult run_pipeline(const PipelineConfig& config);

}  // namespace poreshell
