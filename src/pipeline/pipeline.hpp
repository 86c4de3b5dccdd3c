#pragma once
// The whole job in stage order: input -> grid -> narrow band -> solver -> shell -> mesh and its checks.
// It only orders the stages' calls; perforate() (api.cpp) wraps it for the public API.

#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "band/band.hpp"
#include "core/run_monitor.hpp"
#include "geometry/mesh.hpp"
#include "input/placement.hpp"
#include "measure/hole_table.hpp"
#include "measure/wall_measure.hpp"
#include "pattern/grading.hpp"
#include "pattern/hole_map.hpp"
#include "pattern/pattern.hpp"
#include "pattern/solid_zones.hpp"
#include "pipeline/solve_stage.hpp"
#include "pipeline/stage_options.hpp"
#include "poreshell/geometry.hpp"
#include "poreshell/options.hpp"
#include "reduce/mesh_decimate.hpp"
#include "shell/parts.hpp"
#include "shell/zone_check.hpp"
#include "solver/coarse_start.hpp"
#include "solver/fast_solver.hpp"
#include "solver/model.hpp"
#include "solver/reference_solver.hpp"
#include "solver/time_stepping.hpp"

namespace poreshell {

struct MeshOutput {
  double iso = 0.0;
  TriangleMesh mesh;  // mm, the input's frame
  MeshTopology topology;
  HoleStats holes;                          // on the band at this level, lengths in mm
  std::optional<DecimateResult> reduction;  // max_deviation (the default), max_triangles
  std::string reduction_skipped;            // why the default's reduction was dropped (the full mesh written)
  WallMeasurement wall;                     // across the written solid's wall, mm (shell mode)
  HoleTable hole_table;                     // each pore measured on `mesh` (mm); none for a preview
  std::int64_t spots_at_open_edge = 0;      // of the spots with no hole in the mesh: notches
  PartsSummary parts;                       // what keep_main_parts removed (none with keep_fragments)
  std::int64_t spots_at_iso = 0;            // connected components of {phi > iso} on the band
  std::int64_t pores_from_euler = 0;        // (unperforated chi less its removed voids - chi) / 2
  std::vector<double> pattern;              // a preview: phi per vertex of `mesh`
  ZoneCheck zones;                          // the rim and keep-outs, measured on the holes
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
  std::string wall_source;               // asked | default (kDefaultWallMm) | band (2 delta)
};

struct PipelineResult {
  InputSummary input;
  std::array<int, 3> grid_dims{};
  double h = 0.0;  // in grid units (the longest side is 1); h / input.scale in the input's units
  std::size_t band_voxels = 0, ghosts = 0;
  BandStats band_stats;
  std::size_t band_bytes = 0;
  SolveSummary solve;                     // the model, the run and how it was made
  HoleRequest requested_holes;            // as given
  std::optional<PatternPlan> plan;        // the hole map's choice, when a hole size was asked for
  ZoneAreas zone_areas;                   // the input's area each solid-zone rule keeps (mm^2)
  std::optional<GradingSummary> grading;  // when graded
  // Spots under kLeastSpotAxisRatio cut down to a round hole, or made solid where that left too little
  // (issue 51).
  std::int64_t rounded_oblong_holes = 0, closed_oblong_holes = 0;
  std::int64_t closed_rim_holes = 0;    // spots that would leave less than the rim asked, made solid
  std::int64_t closed_small_holes = 0;  // spots under 0.76 (preview: 0.915) of the asked diameter, made solid
  SpotStats spots;                      // at phi > 0
  std::int64_t unperforated_euler = 0;  // chi of the solid without pores
  SolidSummary solid;
  std::vector<MeshOutput> meshes;
  double seconds_input = 0.0, seconds_band = 0.0, seconds_solve = 0.0, seconds_mesh = 0.0,
         seconds_total = 0.0;
  // Peak resident memory of the process at the end of each stage (bytes; 0 where not measurable).
  std::size_t peak_rss_after_band = 0, peak_rss_after_solve = 0, peak_rss_total = 0;
  int threads = 0;
};

// The narrow volume of Fig. 3(b): phi on the band, 1 on the ghosts and everywhere else; the solid is
// {phi < iso}. Returns its isosurface.
TriangleMesh narrow_volume_mesh(const NarrowBand& band, std::span<const double> phi, double iso);
// Its Euler characteristic, without making it.
std::int64_t narrow_volume_euler(const NarrowBand& band, std::span<const double> phi, double iso);

// The input placed on the grid it will get: what a run and its estimate both begin with (the public
// API's opaque Prepared holds one).
namespace detail {
struct PreparedInput {
  Options given;    // as the caller gave them
  Options options;  // as the run uses them: the hole plan's grid, level and mean
  std::optional<PatternPlan> plan;
  PlacedSurface placed;
  double seconds = 0.0;  // what placing took (a part of the run's input stage)
};
}  // namespace detail
using detail::PreparedInput;
// Validates the options and places the input. Throws as run_pipeline would.
PreparedInput prepare_input(const Input& input, const Options& options);

// Whether the run builds only the band's surface layer (BandOptions::surface_layer): a preview that
// shows the input mesh itself and solves nothing (the even layout's discs as placed). A layer has no
// ghosts and -1 for its outer neighbours, so a preview that runs the equation (the paper's layout)
// needs the whole band (issue 47: solving on the layer wrote past its arrays). A preview of other
// inputs meshes its slab from the whole band.
inline bool builds_surface_layer(const Options& options, const PlacedSurface& placed) {
  return options.preview && placed.mesh.has_value() &&
         resolve_layout(options, holes_in_mm(options)) == Layout::cvt;
}

// Validates the options against the input, runs every stage and checks every mesh; writes nothing.
PipelineResult run_pipeline(const Input& input, const Options& options, RunMonitor& monitor);
// The same from a prepared input (made from this input).
PipelineResult run_pipeline(const Input& input, const PreparedInput& prepared, RunMonitor& monitor);

}  // namespace poreshell
