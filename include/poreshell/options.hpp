#pragma once
// Everything a run can be asked for, in one struct. Lengths are in millimetres (the input's unit is
// stated with the input); the defaults are the paper's section 3.2 values and the CLI's defaults.
// validate() checks an Options alone; perforate() checks it against the input too.

#include <array>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "poreshell/export.hpp"
#include "poreshell/geometry.hpp"

namespace poreshell {

enum class Mode {
  shell,          // a wall of its own thickness, pores straight through it (printable default)
  narrow_volume,  // the paper's Fig. 3(b): the band itself, about 3.8 h thick
};
enum class WallOffset { centered, inside, outside };
enum class SolverKind {
  fast,       // stabilised scheme, band multigrid (docs/solver.md)
  reference,  // the paper's scheme (2.3)-(2.4) by pointwise relaxation
};
enum class InnerIteration { gauss_seidel, jacobi };  // the reference solver's relaxation
// When the run to steady state ends (docs/solver.md "Stop rules").
enum class StopRule {
  automatic,  // holes for a preview and the cvt layout, else paper (docs/solver.md "Stop rules")
  paper,      // the paper's: the consecutive change e_c < tolerance
  holes,      // the hole layout has settled: count, centres and boundaries still over a window of steps
};
enum class Layout {
  automatic,  // cvt for holes asked in mm, paper where the paper's parameters are given
  paper,      // the equation's own layout, as the paper (reproducible figures)
  cvt,        // then Lloyd's iteration of the hole centres and a restart from discs at them
};
enum class PointRoute {
  direct,  // distance to discs fitted to the points (no PDE)
  paper,   // densify, then the segmentation equation (3.3)
};

// Hole-size grading: diameters in mm over the surface (docs/printing.md).
struct Grade {
  enum class Kind {
    axis,    // from_diameter at the model's lowest extent along `axis` to to_diameter at its highest
    line,    // from_diameter at `from` to to_diameter at `to`, constant beyond them
    radial,  // from_diameter at `from`, easing to the base diameter at distance `radius`
    field,   // a vertex field of the input mesh: diameters in mm, or 0..1 mapped to from..to
  } kind = Kind::axis;
  int axis = 2;  // 0, 1, 2: x, y, z
  Point from{}, to{};
  double from_diameter = 0.0, to_diameter = 0.0, radius = 0.0;
  std::string field;    // field: the vertex field's name
  bool mapped = false;  // field: values 0..1 mapped to from_diameter..to_diameter
};

// Parses the CLI's grading spec: axis:x|y|z:D1:D2, line:X,Y,Z:D1:X,Y,Z:D2, radial:X,Y,Z:R:D0,
// field:NAME[:D0:D1]. Throws Error (invalid_option, `grade`).
PORESHELL_API Grade parse_grade(const std::string& text);

// The names of each choice's values: the report's `settings`, Python's keyword values, and (with - for _)
// the command line's. One table per enum, so that every front end spells them alike.
template <class Enum>
struct EnumName {
  std::string_view name;
  Enum value;
};
constexpr std::array<EnumName<Mode>, 2> enum_names(Mode) {
  return {{{"shell", Mode::shell}, {"narrow_volume", Mode::narrow_volume}}};
}
constexpr std::array<EnumName<WallOffset>, 3> enum_names(WallOffset) {
  return {
      {{"centered", WallOffset::centered}, {"inside", WallOffset::inside}, {"outside", WallOffset::outside}}};
}
constexpr std::array<EnumName<SolverKind>, 2> enum_names(SolverKind) {
  return {{{"fast", SolverKind::fast}, {"reference", SolverKind::reference}}};
}
constexpr std::array<EnumName<InnerIteration>, 2> enum_names(InnerIteration) {
  return {{{"gauss_seidel", InnerIteration::gauss_seidel}, {"jacobi", InnerIteration::jacobi}}};
}
constexpr std::array<EnumName<StopRule>, 3> enum_names(StopRule) {
  return {{{"auto", StopRule::automatic}, {"paper", StopRule::paper}, {"holes", StopRule::holes}}};
}
constexpr std::array<EnumName<Layout>, 3> enum_names(Layout) {
  return {{{"auto", Layout::automatic}, {"paper", Layout::paper}, {"cvt", Layout::cvt}}};
}
constexpr std::array<EnumName<PointRoute>, 2> enum_names(PointRoute) {
  return {{{"direct", PointRoute::direct}, {"paper", PointRoute::paper}}};
}
constexpr std::array<EnumName<Grade::Kind>, 4> enum_names(Grade::Kind) {
  return {{{"axis", Grade::Kind::axis},
           {"line", Grade::Kind::line},
           {"radial", Grade::Kind::radial},
           {"field", Grade::Kind::field}}};
}
template <class Enum>
constexpr std::string_view name_of(Enum value) {
  for (const auto& entry : enum_names(Enum{}))
    if (entry.value == value) return entry.name;
  return {};
}
template <class Enum>
constexpr std::optional<Enum> enum_from_name(std::string_view name) {
  for (const auto& entry : enum_names(Enum{}))
    if (entry.name == name) return entry.value;
  return std::nullopt;
}

struct KeepOutSphere {
  Point centre{};  // mm, input frame
  double radius = 0.0;
};
struct KeepOutBox {
  Point min{}, max{};  // mm, input frame
};

// An option's "not given" where 0 is a value: the rim, the paper's model.
inline constexpr double kNotGiven = std::numeric_limits<double>::quiet_NaN();

// The paper's section 3.2 model, where its options are not given and no holes are asked in mm.
struct PaperModel {
  static constexpr double alpha = 1400.0, epsilon_m = 4.0, dt_h = 100.0, phi_bar = -0.3, iso = 0.0;
};

// The shell's wall where holes are asked in mm and no `wall` is given (issue 51: before, 3.81 voxels of
// the hole map's grid, so that the part's thickness changed with the hole size).
inline constexpr double kDefaultWallMm = 2.0;

struct Options {
  // Multiplies the input's coordinates (after its unit): 0.5 prints the model at half size. Every
  // length below, keep-out zones included, is in millimetres of the scaled model.
  double scale = 1.0;

  // Holes in millimetres (0: not given). With a diameter, the hole map chooses alpha, epsilon,
  // phi_bar, the time step, the pore level and the voxel size; the model options below are then unused.
  double hole_diameter = 0.0;
  double spacing = 0.0;   // centre to nearest centre; default diameter / 0.6
  double porosity = 0.0;  // open share of the surface, instead of one of the two lengths
  std::optional<Grade> grade;

  // The grid: points along the longest side, or the voxel size in mm.
  int resolution = 131;
  double voxel_size = 0.0;

  // The printed solid.
  Mode mode = Mode::shell;
  // mm; 0: kDefaultWallMm where holes are asked in mm (a thickness that does not change with the holes),
  // else (the paper's parameters) the band's width 2 delta = 3.81 h.
  double wall = 0.0;
  WallOffset offset = WallOffset::centered;
  // mm of solid along the mesh's open boundary. NaN (the default): half a hole where holes are asked in mm
  // (the fast solver), so that no hole is cut open by the outline; none with the paper's parameters.
  // 0: no rim, holes may be cut by the outline (notches).
  double rim = kNotGiven;
  // Thin parts and sharp creases kept whole (holes asked in mm, mesh inputs): no hole where the part is
  // thinner than thin_feature_ratio times the hole diameter (ears, fingers), nor within half a hole of
  // an edge sharper than crease_angle degrees. 0 turns either off.
  double thin_feature_ratio = 1.5;
  double crease_angle = 40.0;
  std::vector<KeepOutSphere> keep_out;
  std::vector<KeepOutBox> keep_out_boxes;
  std::string keep_out_mask;  // a vertex field of the mesh input: solid where it is 1
  // One part: connected components (specks) and sealed voids under this share of the largest part's
  // volume are removed from the output; larger ones (two input bodies) are kept and reported.
  bool keep_fragments = false;
  double min_part_fraction = 0.01;
  std::int64_t max_triangles = 0;  // reduce each output to at most this many triangles; 0: as meshed
  double max_deviation = 0.02;     // mm, bound on the reduction's distance from the full isosurface (0: none)
  // Reduce as far as max_deviation allows by placed collapses: about 0.55 of the default's triangles for
  // about six times the reduction's time (the way max_triangles always reduces).
  bool lean = false;

  // The paper's model, eq. (2.1), in the paper's frame (the grid's longest side is 1). Not given (NaN,
  // `iso` empty): PaperModel's values, or with holes in mm the hole map's; with holes in mm giving any of
  // them is refused (validate()), since the hole map sets them.
  double alpha = kNotGiven;
  double epsilon_m = kNotGiven;  // epsilon = m h / (2 sqrt 2 atanh 0.9)
  double dt_h = kNotGiven;       // time step in units of h
  double phi_bar = kNotGiven;
  std::vector<double> iso;         // pore levels: one output each
  double initial_amplitude = 0.5;  // phi(x, 0) = phi_bar + amplitude * rand(x), rand in [-1, 1]
  std::uint64_t seed = 1;

  // A preview: the pattern alone on the hole map's grid (never finer), stopped by the holes rule, no
  // shell. Its output is the surface with per-vertex `pattern` values and the band's holes: a mesh
  // input as itself, its edges split down to the grid's resolution; other inputs as a thin slab
  // around the surface.
  bool preview = false;

  // The run.
  StopRule stop = StopRule::automatic;
  // The hole layout: the equation's own (the paper's), or spread as evenly as a centroidal Voronoi
  // tessellation (docs/solver.md "Layout"): the equation's layout, Lloyd's iteration of its hole
  // centres on the surface, and the equation again from discs at those centres.
  Layout layout = Layout::automatic;
  double tolerance = 1e-3;  // the paper's rule: stop when e_c < tolerance
  int max_steps = 2000;
  SolverKind solver = SolverKind::fast;
  double fast_tolerance = 1e-3;    // fast solver: max-norm error bound of each step's solves
  double min_stabilisation = 0.0;  // fast solver: floor on S
  bool coarse_start = true;        // fast solver: form large pores on a coarser grid first
  InnerIteration inner = InnerIteration::gauss_seidel;
  double inner_tolerance = 1e-8;  // reference solver
  int energy_every = 0;           // evaluate the energy (3.2) every K steps; 0: never
  PointRoute point_route = PointRoute::direct;
  double max_memory_gb = 0.0;  // refuse runs estimated to need more; 0: what is available
  int threads = 0;             // worker threads; 0: all cores. Results do not depend on it
};

// Throws Error (invalid_option, naming the option) for a value out of range or two options that
// contradict each other.
PORESHELL_API void validate(const Options& options);

}  // namespace poreshell
