// The option table (include/poreshell/option_table.hpp): each option's description beside the two
// functions that write it to JSON and read it back, so that a new option is one row here.

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <type_traits>
#include <variant>
#include <vector>

#include "core/error.hpp"
#include "io/option_json.hpp"
#include "io/option_range.hpp"
#include "poreshell/option_table.hpp"

namespace poreshell {
namespace {

using nlohmann::json;

constexpr double kNoLimit = std::numeric_limits<double>::infinity();
// 2^53: every integer up to it is exact as a double; the integers' "no limit" (a bound past it is not
// worth a reader's time).
constexpr double kIntMax = 9007199254740992.0;

[[noreturn]] void refuse(const OptionInfo& info, const std::string& what, const json& value) {
  throw OptionError(std::string(info.name),
                    fmt::format("`{}` must be {}; got {}", info.name, what, value.dump()));
}

double number(const OptionInfo& info, const json& v) {
  const bool integral = info.type == OptionType::integer;
  if (!v.is_number() || (integral && !v.is_number_integer())) refuse(info, expected(info), v);
  const double x = v.get<double>();
  if (!in_range(info, x)) refuse(info, expected(info), v);
  return x;
}

// Integers exactly (a seed may use all 64 bits), in the row's range.
template <class T>
T whole_number(const OptionInfo& info, const json& v) {
  if (!v.is_number_integer()) refuse(info, expected(info), v);
  const bool fits =
      v.is_number_unsigned()
          ? v.get<std::uint64_t>() <= static_cast<std::uint64_t>(std::numeric_limits<T>::max()) &&
                static_cast<double>(v.get<std::uint64_t>()) <= info.max &&
                static_cast<double>(v.get<std::uint64_t>()) >= info.min
          : std::is_signed_v<T> && static_cast<double>(v.get<std::int64_t>()) >= info.min &&
                static_cast<double>(v.get<std::int64_t>()) <= info.max;
  if (!fits) refuse(info, expected(info), v);
  return v.is_number_unsigned() ? static_cast<T>(v.get<std::uint64_t>())
                                : static_cast<T>(v.get<std::int64_t>());
}

Point point(const OptionInfo& info, const json& v, const char* what) {
  if (!v.is_array() || v.size() != 3) refuse(info, what, v);
  Point p{};
  for (std::size_t k = 0; k < 3; ++k) {
    if (!v[k].is_number() || !std::isfinite(v[k].get<double>())) refuse(info, what, v);
    p[k] = v[k].get<double>();
  }
  return p;
}

std::vector<KeepOutSphere> spheres(const OptionInfo& info, const json& v) {
  constexpr const char* what = "a list of spheres, [[x, y, z, r], ...] in mm";
  if (!v.is_array()) refuse(info, what, v);
  std::vector<KeepOutSphere> out;
  for (const json& s : v) {
    if (s.is_array() && s.size() == 4) {
      const json centre = {s[0], s[1], s[2]};
      if (!s[3].is_number()) refuse(info, what, s);
      out.push_back({point(info, centre, what), s[3].get<double>()});
    } else if (s.is_object() && s.contains("centre") && s.contains("radius") && s["radius"].is_number()) {
      out.push_back({point(info, s["centre"], what), s["radius"].get<double>()});
    } else {
      refuse(info, what, s);
    }
  }
  return out;
}

std::vector<KeepOutBox> boxes(const OptionInfo& info, const json& v) {
  constexpr const char* what = "a list of boxes, [[x0, y0, z0, x1, y1, z1], ...] in mm";
  if (!v.is_array()) refuse(info, what, v);
  std::vector<KeepOutBox> out;
  for (const json& b : v) {
    if (b.is_array() && b.size() == 6)
      out.push_back({point(info, {b[0], b[1], b[2]}, what), point(info, {b[3], b[4], b[5]}, what)});
    else if (b.is_object() && b.contains("min") && b.contains("max"))
      out.push_back({point(info, b["min"], what), point(info, b["max"], what)});
    else
      refuse(info, what, b);
  }
  return out;
}

json grade_json(const std::optional<Grade>& g) {
  if (!g) return nullptr;
  return {{"kind", std::string(name_of(g->kind))},
          {"axis", g->axis},
          {"from", g->from},
          {"to", g->to},
          {"from_diameter", g->from_diameter},
          {"to_diameter", g->to_diameter},
          {"radius", g->radius},
          {"field", g->field},
          {"mapped", g->mapped}};
}

// null, or the report's object: {"kind": "axis", "axis": 1, "from_diameter": 7, "to_diameter": 10}
// (fields left out keep Grade's defaults).
std::optional<Grade> grade(const OptionInfo& info, const json& v) {
  if (v.is_null()) return std::nullopt;
  constexpr const char* what =
      "null or a grading object, e.g. {\"kind\": \"axis\", \"axis\": 2, "
      "\"from_diameter\": 4, \"to_diameter\": 8}";
  if (!v.is_object() || !v.contains("kind") || !v["kind"].is_string()) refuse(info, what, v);
  const std::optional<Grade::Kind> kind = enum_from_name<Grade::Kind>(v["kind"].get<std::string>());
  if (!kind) refuse(info, what, v);
  Grade g;
  g.kind = *kind;
  for (const auto& item : v.items()) {
    const std::string& key = item.key();
    const json& value = item.value();  // named, not bound: clang 14 does not capture bindings
    const auto length = [&] {
      if (!value.is_number() || !std::isfinite(value.get<double>())) refuse(info, what, v);
      return value.get<double>();
    };
    if (key == "kind") continue;
    if (key == "axis" && value.is_number_integer() && value.get<int>() >= 0 && value.get<int>() <= 2)
      g.axis = value.get<int>();
    else if (key == "from" || key == "to")
      (key == "from" ? g.from : g.to) = point(info, value, what);
    else if (key == "from_diameter")
      g.from_diameter = length();
    else if (key == "to_diameter")
      g.to_diameter = length();
    else if (key == "radius")
      g.radius = length();
    else if (key == "field" && value.is_string())
      g.field = value.get<std::string>();
    else if (key == "mapped" && value.is_boolean())
      g.mapped = value.get<bool>();
    else
      refuse(info, what, v);
  }
  return g;
}

template <class T>
constexpr bool is_list_of_spheres = std::is_same_v<T, std::vector<KeepOutSphere>>;
template <class T>
constexpr bool is_list_of_boxes = std::is_same_v<T, std::vector<KeepOutBox>>;

template <auto Member>
json write(const Options& o) {
  using T = std::remove_cvref_t<decltype(o.*Member)>;
  const T& value = o.*Member;
  if constexpr (std::is_enum_v<T>) {
    return std::string(name_of(value));
  } else if constexpr (is_list_of_spheres<T>) {
    json list = json::array();
    for (const KeepOutSphere& k : value) list.push_back({{"centre", k.centre}, {"radius", k.radius}});
    return list;
  } else if constexpr (is_list_of_boxes<T>) {
    json list = json::array();
    for (const KeepOutBox& k : value) list.push_back({{"min", k.min}, {"max", k.max}});
    return list;
  } else if constexpr (std::is_same_v<T, std::optional<Grade>>) {
    return grade_json(value);
  } else {
    return value;  // numbers (NaN as null), booleans, text, lists of numbers
  }
}

template <auto Member>
void read(Options& o, const OptionInfo& info, const json& v) {
  using T = std::remove_cvref_t<decltype(o.*Member)>;
  T& value = o.*Member;
  if constexpr (std::is_same_v<T, bool>) {
    if (!v.is_boolean()) refuse(info, "true or false", v);
    value = v.get<bool>();
  } else if constexpr (std::is_enum_v<T>) {
    std::string name = v.is_string() ? v.get<std::string>() : "";
    std::replace(name.begin(), name.end(), '-', '_');
    const std::optional<T> e = enum_from_name<T>(name);
    if (!e) refuse(info, fmt::format("one of {}", info.choices), v);
    value = *e;
  } else if constexpr (std::is_integral_v<T>) {
    value = whole_number<T>(info, v);
  } else if constexpr (std::is_same_v<T, double>) {
    // The rim's default is "not given" (NaN), written as null.
    value = v.is_null() && std::isnan(Options{}.*Member) ? Options{}.*Member : number(info, v);
  } else if constexpr (std::is_same_v<T, std::string>) {
    if (!v.is_string()) refuse(info, "a text", v);
    value = v.get<std::string>();
  } else if constexpr (std::is_same_v<T, std::vector<double>>) {
    // Empty: not given (the pore levels' default).
    if (!v.is_array() || (v.empty() && !(Options{}.*Member).empty())) refuse(info, "a list of numbers", v);
    value.clear();
    for (const json& x : v) value.push_back(number(info, x));
  } else if constexpr (is_list_of_spheres<T>) {
    value = spheres(info, v);
  } else if constexpr (is_list_of_boxes<T>) {
    value = boxes(info, v);
  } else {
    value = grade(info, v);
  }
}

struct Row {
  OptionInfo info;
  json (*write)(const Options&);
  void (*read)(Options&, const OptionInfo&, const json&);
};

// The command line's side of a row: its flag, the value's placeholder and --help's text.
struct Flag {
  std::string_view flag, metavar, help;
};

template <auto Member>
Row row(OptionInfo info, Flag flag = {}) {
  info.flag = flag.flag;
  info.metavar = flag.metavar;
  info.flag_help = flag.help;
  info.field = Member;
  return {info, &write<Member>, &read<Member>};
}

// The lower end of a number's range: included, excluded, or included where 0 means "not given".
enum class Min { closed, open, unset };

OptionInfo entry(std::string_view name, std::string_view group, OptionType type, std::string_view help) {
  OptionInfo info;
  info.name = name;
  info.group = group;
  info.type = type;
  info.help = help;
  return info;
}
OptionInfo real(std::string_view name, std::string_view group, std::string_view unit, double min, double max,
                Min kind, std::string_view help, bool max_open = false) {
  OptionInfo info = entry(name, group, OptionType::number, help);
  info.unit = unit;
  info.min = min;
  info.max = max;
  info.min_open = kind == Min::open;
  info.max_open = max_open;
  info.zero_unset = kind == Min::unset;
  return info;
}
OptionInfo whole(std::string_view name, std::string_view group, double min, double max,
                 std::string_view help) {
  OptionInfo info = entry(name, group, OptionType::integer, help);
  info.min = min;
  info.max = max;
  return info;
}
OptionInfo other(std::string_view name, std::string_view group, OptionType type, std::string_view help,
                 std::string_view choices = {}) {
  OptionInfo info = entry(name, group, type, help);
  info.choices = choices;
  return info;
}
OptionInfo levels(std::string_view name, std::string_view group, double min, double max,
                  std::string_view help) {
  OptionInfo info = entry(name, group, OptionType::numbers, help);
  info.min = min;
  info.max = max;
  info.min_open = info.max_open = true;
  return info;
}

// The ranges are what a JSON value must meet and what validate() checks on every Options, however made
// (check_range); the CLI's flags check only the sign (command_line.cpp). One row per option: the function
// is as long as the options are many, and kept whole so that the table reads as one list.
const std::vector<Row>& rows() {
  constexpr Min open = Min::open, closed = Min::closed, unset = Min::unset;
  constexpr bool below_max = true;  // real()'s last argument: the range excludes its max
  static const std::vector<Row> table = {
      row<&Options::scale>(
          real("scale", "holes", "", 0, kNoLimit, open,
               "multiplies the input's coordinates after its unit (0.5: half size)"),
          {"--scale", "F",
           "multiply the input's coordinates by F (after --units); lengths on the command line "
           "are in mm of the scaled model"}),
      row<&Options::resolution>(
          whole("resolution", "model", 9, 2048, "grid points along the longest side"),
          {"--resolution", "N",
           "grid points N_x along the longest side, h = 1/(N_x - 1) (paper: 131, Fig. 5: 181)"}),
      row<&Options::voxel_size>(
          real("voxel_size", "model", "mm", 0, kNoLimit, unset,
               "grid spacing instead of resolution; 0: from the holes or resolution"),
          {"--voxel-size", "MM", "grid spacing h in mm; sets the resolution instead of --resolution"}),
      row<&Options::mode>(
          other("mode", "solid", OptionType::choice, "the printed solid", "shell, narrow_volume"),
          {"--mode", "",
           "shell: wall of --wall mm, pores straight through it; narrow-volume: the paper's Fig. 3b (about "
           "3.8 h "
           "thick)"}),
      row<&Options::wall>(real("wall", "solid", "mm", 0, kNoLimit, unset,
                               "wall thickness; 0: 2 mm for holes in mm, else the band's width"),
                          {"--wall", "MM",
                           "shell wall thickness in mm (default: 2 mm with holes in mm; with the paper's "
                           "parameters the band's width 2 delta = 3.81 h)"}),
      row<&Options::offset>(
          other("offset", "solid", OptionType::choice, "the wall's side of the surface",
                "centered, inside, outside"),
          {"--offset", "", "where the shell wall lies: centered on the surface, inside or outside it"}),
      row<&Options::rim>(
          real("rim", "zones", "mm", 0, kNoLimit, closed,
               "solid along the open boundary; null: half a hole for holes in mm"),
          {"--rim", "MM",
           "solid rim of this width (mm) along the mesh's open boundary (default: half a hole with "
           "holes in mm, so that none is cut open; 0: none)"}),
      row<&Options::thin_feature_ratio>(
          real("thin_feature_ratio", "zones", "", 0, kNoLimit, closed,
               "no hole where the part is thinner than this times a hole; 0: off"),
          {"--thin-features", "RATIO",
           "no hole where the part is thinner than this many hole diameters (ears, fingers); 0: off"}),
      row<&Options::crease_angle>(
          real("crease_angle", "zones", "degrees", 0, 180, closed,
               "no hole within half a hole of a sharper edge; 0: off", below_max),
          {"--crease-angle", "DEG",
           "no hole within half a hole of an edge sharper than this (degrees); 0: off"}),
      row<&Options::keep_out>(
          other("keep_out", "zones", OptionType::spheres, "spheres kept solid, [[x, y, z, r], ...] in mm"),
          {"--keep-out", "X,Y,Z,R",
           "solid sphere X,Y,Z,R in mm (input frame) where no pore may form; repeatable"}),
      row<&Options::keep_out_boxes>(
          other("keep_out_boxes", "zones", OptionType::boxes,
                "boxes kept solid, [[x0, y0, z0, x1, y1, z1], ...] in mm"),
          {"--keep-out-box", "X0,Y0,Z0,X1,Y1,Z1",
           "solid box X0,Y0,Z0,X1,Y1,Z1 in mm (input frame, two opposite corners); repeatable"}),
      row<&Options::keep_out_mask>(
          other("keep_out_mask", "zones", OptionType::text,
                "a vertex field of the mesh input: solid where it is 1"),
          {"--keep-out-mask", "NAME",
           "solid wherever this vertex property of the --mesh PLY file is 1 (a painted 0/1 mask)"}),
      row<&Options::keep_fragments>(
          other("keep_fragments", "output", OptionType::boolean,
                "keep specks and sealed voids instead of removing them"),
          {"--keep-fragments", "",
           "keep specks and sealed voids under 1% of the largest part's volume (removed by default)"}),
      row<&Options::min_part_fraction>(real("min_part_fraction", "output", "", 0, 1, closed,
                                            "parts and voids under this share of the largest are removed")),
      row<&Options::max_triangles>(whole("max_triangles", "output", 0, kIntMax,
                                         "reduce each output to at most this many; 0: no count"),
                                   {"--max-triangles", "N",
                                    "reduce each output to at most N triangles, keeping it closed, manifold "
                                    "and within --max-deviation "
                                    "of the full isosurface; fails naming the fewest that keep the bound"}),
      row<&Options::max_deviation>(
          real("max_deviation", "output", "mm", 0, kNoLimit, closed,
               "bound on the reduction's distance from the full isosurface; 0: none"),
          {"--max-deviation", "MM",
           "the written surface lies within this distance (mm, both ways, checked) of the full isosurface, "
           "with fewer triangles where the shape allows; 0: the full isosurface"}),
      row<&Options::lean>(
          other("lean", "output", OptionType::boolean,
                "reduce as far as max_deviation allows with placed vertices: about half the triangles, "
                "several times the time"),
          {"--lean", "",
           "fewer triangles within --max-deviation (the demo bunny: 376 k instead of 724 k) for about six "
           "times the reduction's time"}),
      row<&Options::alpha>(
          real("alpha", "model", "", 0, kNoLimit, closed,
               "the model's alpha (2.1); null: 1400, the paper's (not with holes in mm)"),
          {"--alpha", "A",
           "nonlocal strength α in eq. (2.1) (default 1400, the paper's sphere and torus; its bunny: 2200)"}),
      row<&Options::epsilon_m>(
          real("epsilon_m", "model", "", 0, kNoLimit, open,
               "epsilon = m h / (2 sqrt 2 atanh 0.9); null: 4, the paper's (not with holes in mm)"),
          {"--epsilon-m", "M", "interface width m in ε_m = m h / (2√2 tanh⁻¹ 0.9) (default 4, the paper's)"}),
      row<&Options::dt_h>(real("dt_h", "model", "h", 0, kNoLimit, open,
                               "time step in units of h; null: 100, the paper's (not with holes in mm)"),
                          {"--dt-h", "K", "time step Δt in units of h, Δt = K h (default 100, the paper's)"}),
      row<&Options::iso>(
          levels("iso", "output", -1, 1, "pore levels, one output each; empty: 0 (not with holes in mm)"),
          {"--iso", "C[,C...]",
           "isosurface level(s) φ = C of the narrow volume, comma-separated or repeated "
           "(default 0; the paper's figures: 0.3, 0, -0.3)"}),
      row<&Options::phi_bar>(
          real("phi_bar", "model", "", -1, 1, open,
               "mean of phi (the solid share); null: -0.3, the paper's (not with holes in mm)", below_max),
          {"--phi-bar", "F",
           "mean concentration φ̄ in eq. (2.1), sets the pore fraction (default -0.3, the paper's)"}),
      // After the model rows they replace: the CLI adds flags in this order, and CLI11 names the first
      // flag given in a clash ("--alpha excludes --hole-diameter").
      row<&Options::hole_diameter>(
          real("hole_diameter", "holes", "mm", 0, kNoLimit, unset,
               "hole diameter; 0: not given (the paper's parameters)"),
          {"--hole-diameter", "MM",
           "hole diameter in mm; sets alpha, epsilon, phi-bar, the time step, the pore "
           "level and the voxel size (docs/printing.md)"}),
      row<&Options::spacing>(
          real("spacing", "holes", "mm", 0, kNoLimit, unset, "centre to nearest centre; 0: diameter / 0.6"),
          {"--spacing", "MM", "hole centre spacing in mm (default with --hole-diameter: diameter / 0.6)"}),
      row<&Options::porosity>(real("porosity", "holes", "", 0, 1, unset,
                                   "open share of the surface, instead of spacing; 0: not given"),
                              {"--porosity", "F", "open share of the surface, instead of --spacing"}),
      row<&Options::grade>(other("grade", "holes", OptionType::grade,
                                 "hole diameters graded over the surface (axis, line, radial, field)"),
                           {"--grade", "SPEC",
                            "hole-size grading, diameters in mm: axis:x|y|z:D1:D2, line:X,Y,Z:D1:X,Y,Z:D2, "
                            "radial:X,Y,Z:R:D0 or field:NAME[:D0:D1] (a PLY vertex property)"}),
      row<&Options::initial_amplitude>(real("initial_amplitude", "model", "", 0, kNoLimit, closed,
                                            "amplitude of the initial condition's noise")),
      row<&Options::seed>(whole("seed", "holes", 0, 18446744073709551615.0, "seed of the initial condition"),
                          {"--seed", "S", "seed of rand(x) in φ(x, 0) = φ̄ + 0.5 rand(x)"}),
      row<&Options::preview>(
          other("preview", "run", OptionType::boolean, "the pattern alone on the surface, in about a second"),
          {"--preview", "",
           "the pattern alone, fast: the surface with its holes painted on (.ply with vertex colours, "
           "--html), "
           "no shell; with --layout cvt the full run's starting discs, else the equation stopped as soon as "
           "the hole layout has settled"}),
      row<&Options::stop>(
          other("stop", "solver", OptionType::choice, "when the run to steady state ends",
                "auto, paper, holes"),
          {"--stop", "",
           "when the run ends: holes (the hole count, centres and boundaries have settled; the "
           "default with --layout cvt and for --preview) or paper (e_c < --tol; the default with "
           "--layout paper)"}),
      row<&Options::layout>(
          other("layout", "solver", OptionType::choice, "the hole layout", "auto, paper, cvt"),
          {"--layout", "",
           "the hole layout: cvt (the equation started from discs at a centroidal Voronoi tessellation of "
           "the "
           "free surface at its own hole density; the default with --hole-diameter, which it needs) or paper "
           "(the pattern forming from noise; the default with the paper's parameters)"}),
      row<&Options::tolerance>(
          real("tolerance", "solver", "", 0, kNoLimit, open, "stop when e_c < tolerance"),
          {"--tol", "T", "stop when the consecutive change e_c < tol (paper: 1e-3)"}),
      row<&Options::max_steps>(
          whole("max_steps", "solver", 1, kIntMax, "time steps at most"),
          {"--max-steps", "S", "at most S time steps (paper: T = 329 Δt sphere, 358 Δt torus)"}),
      row<&Options::solver>(
          other("solver", "solver", OptionType::choice, "the solver", "fast, reference"),
          {"--solver", "",
           "fast: stabilised scheme, band multigrid (docs/solver.md); reference: the paper's scheme"}),
      row<&Options::fast_tolerance>(
          real("fast_tolerance", "solver", "", 0, kNoLimit, open, "fast solver: error bound of each solve"),
          {"--fast-tol", "T", "fast solver: bound on the error of each step's solve"}),
      row<&Options::min_stabilisation>(
          real("min_stabilisation", "solver", "", 0, kNoLimit, closed, "fast solver: floor on S"),
          {"--min-stabilisation", "S",
           "fast solver: floor on the stabilisation S (default: the energy-stability bound alone)"}),
      row<&Options::coarse_start>(
          other("coarse_start", "solver", OptionType::boolean,
                "fast solver: form large pores on a coarser grid first"),
          {"--coarse-start", "",
           "fast solver: auto forms the pattern on a coarser grid first where epsilon spans 1.8 eps_4 or "
           "more "
           "(fine voxels for large pores), then relaxes it here; off solves here from the start"}),
      row<&Options::inner>(other("inner", "solver", OptionType::choice, "reference solver: inner relaxation",
                                 "gauss_seidel, jacobi"),
                           {"--inner", "", "reference solver: inner relaxation per step (paper: jacobi)"}),
      row<&Options::inner_tolerance>(
          real("inner_tolerance", "solver", "", 0, kNoLimit, open, "reference solver: inner tolerance"),
          {"--inner-tol", "T", "inner tolerance on the max-norm scaled residual of eqs. (2.3)-(2.4)"}),
      row<&Options::energy_every>(
          whole("energy_every", "run", 0, kIntMax, "evaluate the energy every K steps; 0: never"),
          {"--energy-every", "K",
           "evaluate the discrete energy (3.2) every K steps and at the end; 0 = never (saves its Poisson "
           "factorisation on large grids)"}),
      row<&Options::point_route>(
          other("point_route", "model", OptionType::choice, "point clouds' route", "direct, paper"),
          {"--point-route", "",
           "point clouds: direct (distance to discs fitted to the points, no PDE) or paper (densify, then "
           "the "
           "segmentation eq. 3.3; needs a closed surface); docs/point-clouds.md"}),
      row<&Options::max_memory_gb>(
          real("max_memory_gb", "run", "GB", 0, kNoLimit, unset,
               "refuse runs estimated to need more; 0: what is available"),
          {"--max-memory", "GB",
           "refuse runs estimated to need more memory than this, in GB (default: what is available)"}),
      row<&Options::threads>(whole("threads", "run", 0, 4096, "worker threads; 0: all cores"),
                             {"--threads", "N", "worker threads (oneTBB); 0 = all cores"}),
  };
  return table;
}

}  // namespace

bool in_range(const OptionInfo& info, double x) {
  return std::isfinite(x) && (info.min_open ? x > info.min : x >= info.min) &&
         (info.max_open ? x < info.max : x <= info.max);
}

std::string expected(const OptionInfo& info) {
  std::string text = info.type == OptionType::integer   ? "a whole number"
                     : info.type == OptionType::numbers ? "numbers"
                                                        : "a number";
  if (!info.unit.empty()) text += fmt::format(" in {}", info.unit);
  const bool low = info.min > -kNoLimit, high = info.max < kIntMax;
  const auto from = [&] { return fmt::format("{} {:g}", info.min_open ? "above" : "at least", info.min); };
  const auto to = [&] { return fmt::format("{} {:g}", info.max_open ? "below" : "at most", info.max); };
  if (low && high && info.min_open == info.max_open)
    text += info.min_open ? fmt::format(", strictly between {:g} and {:g}", info.min, info.max)
                          : fmt::format(", from {:g} to {:g}", info.min, info.max);
  else if (low && high)
    text += ", " + from() + " and " + to();
  else if (low)
    text += ", " + from();
  return text;
}

void check_range(const OptionInfo& info, const Options& options) {
  if (info.type != OptionType::number && info.type != OptionType::integer && info.type != OptionType::numbers)
    return;
  const auto check = [&](double x, double default_value) {
    if (std::isnan(x) && std::isnan(default_value)) return;
    if (in_range(info, x)) return;
    throw OptionError(std::string(info.name),
                      fmt::format("`{}` must be {}; got {:g} ({})", info.name, expected(info), x, info.help));
  };
  std::visit(
      [&](auto member) {
        using T = std::remove_cvref_t<decltype(options.*member)>;
        if constexpr (std::is_same_v<T, std::vector<double>>) {
          for (const double x : options.*member) check(x, 0.0);
        } else if constexpr (std::is_arithmetic_v<T>) {
          static const Options defaults;
          check(static_cast<double>(options.*member), static_cast<double>(defaults.*member));
        }
      },
      info.field);
}

std::span<const OptionInfo> option_table() {
  static const std::vector<OptionInfo> infos = [] {
    std::vector<OptionInfo> out;
    for (const Row& r : rows()) out.push_back(r.info);
    return out;
  }();
  return infos;
}

const OptionInfo* find_option(std::string_view name) {
  for (const OptionInfo& info : option_table())
    if (info.name == name) return &info;
  return nullptr;
}

json options_json(const Options& options) {
  json out = json::object();
  for (const Row& r : rows()) out[std::string(r.info.name)] = r.write(options);
  return out;
}

Options options_from_json_object(const json& settings) {
  if (!settings.is_object())
    throw OptionError("",
                      fmt::format("options must be a JSON object by option name; got {}", settings.dump()));
  Options options;
  for (const auto& item : settings.items()) {
    const std::string& name = item.key();
    const json& value = item.value();
    const auto row =
        std::find_if(rows().begin(), rows().end(), [&](const Row& r) { return r.info.name == name; });
    if (row == rows().end())
      throw OptionError(name,
                        fmt::format("`{}` is not an option (the report's `settings` lists them all)", name));
    row->read(options, row->info, value);
  }
  return options;
}

}  // namespace poreshell
