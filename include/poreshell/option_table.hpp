#pragma once
// Every option of Options by its API name, once: its group, type, unit, valid range and help. The
// report's `settings`, a project file and the studio's HTTP API read and write options through it as
// JSON (the Python keywords and the CLI's flags, with - for _, use the same names).

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "poreshell/export.hpp"
#include "poreshell/options.hpp"

namespace poreshell {

enum class OptionType {
  number,   // a real number
  integer,  // a whole number
  boolean,  // true or false
  choice,   // one of the names of an enum (enum_names)
  text,     // a string
  numbers,  // a list of numbers (iso levels)
  spheres,  // keep-out spheres: [[x, y, z, r], ...] or [{"centre": [x, y, z], "radius": r}, ...]
  boxes,    // keep-out boxes: [[x0, y0, z0, x1, y1, z1], ...] or [{"min": [...], "max": [...]}, ...]
  grade,    // null or the report's object: {"kind": "axis", "axis": 1, "from_diameter": 7, ...}
};

// The Options member an entry reads and writes, for a front end that binds it by its type (the CLI).
using OptionField =
    std::variant<double Options::*, int Options::*, std::int64_t Options::*, std::uint64_t Options::*,
                 bool Options::*, std::string Options::*, std::vector<double> Options::*,
                 std::vector<KeepOutSphere> Options::*, std::vector<KeepOutBox> Options::*,
                 std::optional<Grade> Options::*, Mode Options::*, WallOffset Options::*,
                 SolverKind Options::*, InnerIteration Options::*, StopRule Options::*, Layout Options::*,
                 PointRoute Options::*>;

struct OptionInfo {
  std::string_view name;   // the API name (Python keyword; the CLI's flag with - for _)
  std::string_view group;  // holes, model, solid, zones, output, solver, run
  OptionType type = OptionType::number;
  std::string_view unit;        // "mm", "degrees", "GB", ... or empty
  double min = 0.0, max = 0.0;  // numbers, integers: the valid range, its ends included unless open
  bool min_open = false;        // the range excludes min itself (> rather than >=)
  bool max_open = false;        // the range excludes max itself (< rather than <=)
  std::string_view help;        // one line, for --help, the studio's fields
  std::string_view choices;     // choice: the names, comma separated
  // 0, the default, means "not given" (the hole map's lengths, the wall, ...): a flag gives more.
  bool zero_unset = false;
  // The command line: the flag ("--tol"; empty: none), its value's placeholder in --help ("MM") and
  // its --help text, which may name other flags and say more than `help`.
  std::string_view flag, metavar, flag_help;
  OptionField field;
};

// In the order of the CLI's --help (the report's `settings` are sorted by name).
PORESHELL_API std::span<const OptionInfo> option_table();
// The entry of `name`, or null.
PORESHELL_API const OptionInfo* find_option(std::string_view name);

// Every option as a JSON object by API name (the report's `settings`), as text.
PORESHELL_API std::string options_to_json(const Options& options);
// Options from a JSON object by API name; options it does not name keep their defaults. Throws Error
// (invalid_option) naming the option for an unknown name, a value of the wrong type or out of range,
// or a text that is not a JSON object; the result is then also checked by validate().
PORESHELL_API Options options_from_json(std::string_view json_text);

}  // namespace poreshell
