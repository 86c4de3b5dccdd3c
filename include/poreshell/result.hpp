#pragma once
// What a run returns: the solid's mesh per pore level (in mm, in the input's frame), the table of its
// holes measured on that mesh, and the report (the JSON report's content as a struct).

#include <array>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "poreshell/geometry.hpp"
#include "poreshell/options.hpp"

namespace poreshell {

// One hole through the wall, measured on the output mesh: its cross-section at mid-wall.
struct Hole {
  Point centre{};            // mm, input frame
  Point normal{};            // unit surface normal
  double diameter = 0.0;     // mm, sqrt(4 A / pi) of the cross-section's area A
  double circularity = 0.0;  // 4 pi A / P^2 (1 for a circle)
  double nearest = 0.0;      // mm, to the nearest other hole's centre (0 when alone)
  double axis_ratio = 0.0;   // minor over major axis of the cross-section (b / a for an ellipse; 1 round)
  // mm, the diameter asked for at its centre: the request, or the grading's there (as clamped); 0 where
  // no hole size was asked (the paper's parameters).
  double asked_diameter = 0.0;
};

struct TopologyReport {
  std::int64_t vertices = 0, triangles = 0, euler_characteristic = 0, components = 0;
  bool closed = false, manifold = false, oriented = false;
  double volume = 0.0;  // mm^3
  double min_angle_degrees = 0.0;
};

// Hole statistics from the band's spots at one level (lengths in mm).
struct SpotHoleStats {
  std::int64_t count = 0;
  double diameter_mean = 0.0, diameter_cv = 0.0, spacing_mean = 0.0, spacing_cv = 0.0, porosity = 0.0;
  double cell_area_cv = 0.0;  // of the holes' Voronoi cells on the surface: how evenly they are spread
};

struct ReductionReport {
  std::int64_t triangles_before = 0, triangles_after = 0;
  double max_distance = 0.0;  // mm
  bool reached_target = false;
  // mm: the largest distance found by sampling both surfaces apart from the reduction's own points
  // (within max_distance), and how many points that measured.
  double sampled_distance = 0.0;
  std::int64_t sampled_points = 0;
};

struct WallReport {
  double median = 0.0, min = 0.0, max = 0.0;  // mm, across the written solid's wall
  double low = 0.0, high = 0.0;               // mm, 5th and 95th percentiles of the probes
  std::int64_t probes = 0;
  std::int64_t merged = 0;  // probes over 1.5 medians: a part thinner than two walls, filled solid
};

// One output: the solid at one pore level.
struct LevelReport {
  double iso = 0.0;
  std::string path;  // set when saved
  TopologyReport topology;
  SpotHoleStats holes;
  std::optional<ReductionReport> reduction;
  WallReport wall;
  struct {
    std::int64_t parts = 0;  // connected components written (1: one part; a kept cavity counts too)
    std::int64_t removed_fragments = 0, removed_voids = 0;
    std::int64_t removed_wall_voids = 0;  // of the voids, those the wall without pores has as well
    double removed_volume = 0.0;          // mm^3
    // Sealed cavities of a perforated solid at or above min_part_fraction, filled solid (none kept).
    std::int64_t filled_cavities = 0;
    double filled_volume = 0.0, largest_filled_volume = 0.0;  // mm^3
  } parts;
  std::int64_t spots_at_iso = 0;  // connected components of {phi > iso} on the band
  // (chi of the unperforated solid less its voids removed here too - chi) / 2: the pores, each a tunnel
  std::int64_t pores_from_euler = 0;
  std::int64_t hole_table_dropped = 0;  // band spots that are no pore of the mesh (notches at an open edge)
  // Of those, the spots around which no closed hole was measured: at the open boundary (notches), or
  // elsewhere (not cut through the wall, or a loop the measure missed); and the rest of
  // hole_table_dropped, spots another one's hole took in.
  std::int64_t spots_at_open_edge = 0, spots_not_through = 0, spots_in_another_hole = 0;
  // What the solid zones asked for, measured on this output's holes (mm; NaN where it does not apply):
  // the least distance from a hole's edge to the open boundary (the rim left), and to a keep-out
  // (negative: a hole reaches in; holes_in_keep_outs counts those).
  struct {
    double rim_asked = 0.0;  // the rim applied: Options::rim, or its default (half a hole, holes in mm)
    double rim = std::numeric_limits<double>::quiet_NaN();
    double keep_out_clearance = std::numeric_limits<double>::quiet_NaN();
    std::int64_t holes_in_keep_outs = 0;
  } zones;
};

struct Report {
  std::string version;                    // the library's (poreshell::version())
  std::vector<std::string> command_line;  // set by a front end (the CLI's arguments); empty otherwise
  Options settings;                       // every option as given to perforate()
  struct {
    std::string kind;  // shape, mesh or points
    std::string name;
    std::int64_t vertices = 0, triangles = 0, boundary_edges = 0, dropped_degenerate = 0;
    std::int64_t euler_characteristic = 0;
    double scale_to_grid = 1.0;  // grid units per input unit
    std::string units = "mm";
    double mm_per_unit = 1.0;
    std::string point_route;
    std::int64_t densified_points = 0;
    int segmentation_iterations = 0;
    std::int64_t thin_vertices = 0,
                 crease_edges = 0;       // kept solid (Options::thin_feature_ratio, crease_angle)
    std::int64_t dropped_duplicate = 0;  // repeats of a triangle (the same three vertices), dropped
  } input;
  std::array<int, 3> grid_dims{};
  double h = 0.0;  // grid units (the longest side is 1)
  double h_mm = 0.0;
  struct {
    std::string mode, offset;
    double wall_mm = 0.0, spacing_mm = 0.0, seconds_sample = 0.0;
    std::int64_t samples = 0, incomplete_stencils = 0;
    // Where wall_mm came from: "asked" (Options::wall), "default" (kDefaultWallMm, holes in mm) or "band"
    // (2 delta: the paper's parameters, the narrow volume).
    std::string wall_source;
  } solid;
  struct {
    std::int64_t voxels = 0, ghosts = 0, paper_ghosts = 0, closure_added = 0, bytes = 0;
  } band;
  struct {
    double alpha = 0.0, epsilon = 0.0, phi_bar = 0.0, dt = 0.0;  // the paper's frame
    // (1 - 3 phi_bar^2)^2 > 4 alpha eps^2: the uniform state is unstable, so a pattern forms.
    bool pattern_can_form = true;
  } model;
  struct Request {
    double diameter = 0.0, spacing = 0.0, porosity = 0.0;
  } requested;
  struct Plan {
    double diameter = 0.0, spacing = 0.0, porosity = 0.0, pore_level = 0.0, voxel_size = 0.0;
    double alpha_per_mm2 = 0.0, epsilon_mm = 0.0, phi_bar = 0.0;
  };
  std::optional<Plan> plan;  // the hole map's choice, when holes were asked in mm
  // The input surface's area each rule keeps solid (mm^2; overlaps count in each; `solid` is their union),
  // mesh inputs with holes in mm; zeros otherwise.
  struct {
    double surface = 0.0, thin = 0.0, creases = 0.0, rims = 0.0, keep_outs = 0.0, solid = 0.0;
  } solid_zones;
  // What a reader of the figures should not miss: the achieved porosity under 60% of the request's.
  std::vector<std::string> warnings;
  struct Grading {
    double min_diameter = 0.0, max_diameter = 0.0, clamped_fraction = 0.0, printable_min = 0.0,
           printable_max = 0.0;
  };
  std::optional<Grading> grading;
  struct CoarseStart {
    std::array<int, 3> grid{};
    double h_mm = 0.0, h = 0.0, final_ec = 0.0, seconds = 0.0;
    std::int64_t band_voxels = 0, steps = 0, inner_iterations = 0, repeated_steps = 0, spots = 0;
    bool reached_tolerance = false;
  };
  struct {
    std::string name, inner_iteration;
    std::int64_t steps = 0, inner_iterations = 0, repeated_steps = 0;
    double final_ec = 0.0, tolerance = 0.0;
    bool reached_tolerance = false, inner_converged = true;  // reached_tolerance: the stop rule was met
    std::string stop_rule;                                   // paper (e_c < tolerance) or holes
    std::string layout;                                      // paper or cvt (Options::layout)
    std::int64_t layout_holes = 0;                           // cvt: the discs the run started from
    std::optional<CoarseStart> coarse_start;
    double energy_first = 0.0, energy_last = 0.0;  // NaN when not evaluated
    std::vector<std::pair<int, double>> energy_trace;
  } solver;
  struct {
    std::int64_t spots = 0;
    // Spots squeezed next to a solid zone (pinholes) made solid: narrower than 0.76 of the asked diameter
    // by their band area, so that no written hole is under 0.7 (docs/printing.md "Pinholes closed"). A
    // preview's discs under 0.915, which the run closes (docs/solver.md "Layout").
    std::int64_t closed_small_holes = 0;
    double size_cv = 0.0, mean_size_voxels = 0.0, area_fraction = 0.0, spacing_mean_voxels = 0.0,
           spacing_cv = 0.0;
    // Spots whose axis ratio on the surface is under 0.8 (a slot between solid zones, across a crease,
    // on a tight bend), so that no written hole is oblong (issue 51): made solid where the round hole
    // left of them would be a pinhole or is not round either (closed), else cut down to it (rounded).
    std::int64_t closed_oblong_holes = 0;
    std::int64_t rounded_oblong_holes = 0;
    // Spots that would leave less than the asked rim (as discs of their area), made solid (issue 51).
    std::int64_t closed_rim_holes = 0;
  } pattern;
  std::vector<LevelReport> outputs;
  std::int64_t unperforated_euler_characteristic = 0;
  struct {
    std::int64_t band_bytes = 0, solver_bytes = 0, peak_rss_after_band = 0, peak_rss_after_solve = 0,
                 peak_rss_total = 0;
  } memory;
  struct {
    double input = 0.0, band = 0.0, solve = 0.0, mesh = 0.0, total = 0.0;
  } seconds;
  int threads = 0;
  bool preview = false;  // a preview: the pattern alone, no shell (outputs carry `pattern`)
};

struct Output {
  double iso = 0.0;
  Mesh mesh;                // mm, input frame; closed, manifold, outward oriented
  std::vector<Hole> holes;  // measured on `mesh` (a preview: the band's spots, circularity 0)
  // A preview only: the order parameter phi per vertex of `mesh`; open (a hole) where pattern > iso.
  std::vector<double> pattern;
};

struct Result {
  std::vector<Output> outputs;  // one per pore level (Options::iso, or the hole map's level)
  Report report;
};

}  // namespace poreshell
