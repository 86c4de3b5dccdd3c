// The command line: argv -> Command (poreshell::Options and the files). Parsing only; main.cpp runs it.
// The options' flags come from the option table (poreshell/option_table.hpp); the flags declared here
// by hand are the command line's own: the input, the files written, the time budget and the display.

#include "command_line.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <type_traits>

#include "cli_support.hpp"
#include "poreshell/option_table.hpp"

namespace {

using poreshell::OptionInfo;

const std::map<std::string, poreshell::Unit> kUnits{{"m", poreshell::Unit::m},
                                                    {"cm", poreshell::Unit::cm},
                                                    {"mm", poreshell::Unit::mm},
                                                    {"inch", poreshell::Unit::inch}};

std::string flag_spelling(std::string_view name) {
  std::string flag(name);
  std::replace(flag.begin(), flag.end(), '_', '-');
  return flag;
}

// The library's names of an option's values, with - for _ as flags are spelled. Static: the validator
// keeps a reference.
template <class Enum>
const std::map<std::string, Enum>& flag_names() {
  static const std::map<std::string, Enum> names = [] {
    std::map<std::string, Enum> out;
    for (const auto& [name, value] : poreshell::enum_names(Enum{})) out.emplace(flag_spelling(name), value);
    return out;
  }();
  return names;
}

// Like CLI::CheckedTransformer, with a message that lists the names alone: "--units: 'furlong' is not
// one of cm, inch, m, mm".
template <class Enum>
CLI::Validator one_of(const std::map<std::string, Enum>& names) {
  std::string list;
  for (const auto& entry : names) list += (list.empty() ? "" : ", ") + entry.first;
  return CLI::Validator(
      [&names, list](std::string& text) -> std::string {
        const auto it = names.find(text);
        if (it == names.end()) return "'" + text + "' is not one of " + list;
        text = std::to_string(static_cast<int>(it->second));
        return {};
      },
      "", "");
}

// The text of the flags parsed after CLI11: keep-out zones, the grading and on-by-default switches.
struct FlagText {
  std::map<const OptionInfo*, std::vector<std::string>> lists;  // keep-out spheres and boxes
  std::map<const OptionInfo*, std::string> grades;
  std::map<const OptionInfo*, std::string> switches;  // auto|off
};

// The check a number's flag makes itself: the sign its row's range implies (> 0 where 0 is excluded or
// means "not given"). The rest of the range (resolution's 9, phi_bar's ±1, 4096 threads) is left to
// validate(), whose messages say why.
std::optional<CLI::Validator> sign_check(const OptionInfo& info) {
  if (info.min < 0.0) return std::nullopt;
  return number_above(0.0, info.min == 0.0 && !info.min_open && !info.zero_unset);
}

// One row's flag, bound to its Options member by the member's type.
CLI::Option* add_table_flag(CLI::App& app, const OptionInfo& info, poreshell::Options& options,
                            FlagText& text) {
  const std::string flag(info.flag), help(info.flag_help);
  return std::visit(
      [&](auto member) -> CLI::Option* {
        using T = std::remove_cvref_t<decltype(options.*member)>;
        auto& value = options.*member;
        const poreshell::Options defaults;
        CLI::Option* option = nullptr;
        if constexpr (std::is_same_v<T, bool>) {
          if (!(defaults.*member)) return app.add_flag(flag, value, help);
          // On by default: a bare flag could not turn it off.
          text.switches[&info] = "auto";
          return app.add_option(flag, text.switches[&info], help)
              ->check(CLI::IsMember({"auto", "off"}))
              ->capture_default_str();
        } else if constexpr (std::is_enum_v<T>) {
          return app.add_option(flag, value, help)
              ->transform(one_of(flag_names<T>()))
              ->default_str(flag_spelling(poreshell::name_of(defaults.*member)));
        } else if constexpr (std::is_arithmetic_v<T>) {
          option = app.add_option(flag, value, help);
          if (const auto check = sign_check(info)) option->check(*check);
          // A default that means "not given" is not shown (NaN: the rim's, the paper's model's).
          bool given = !info.zero_unset;
          if constexpr (std::is_floating_point_v<T>) given = given && !std::isnan(defaults.*member);
          if (given) option->capture_default_str();
        } else if constexpr (std::is_same_v<T, std::vector<double>>) {
          option = app.add_option(flag, value, help)
                       ->delimiter(',')
                       ->allow_extra_args(false);  // one token per flag: "--iso 0.3 OUT" takes no stray word
          // Empty, "not given" (the pore levels'), is not shown.
        } else if constexpr (std::is_same_v<T, std::string>) {
          option = app.add_option(flag, value, help);
        } else if constexpr (std::is_same_v<T, std::optional<poreshell::Grade>>) {
          option = app.add_option(flag, text.grades[&info], help);
        } else {  // keep-out spheres and boxes
          option = app.add_option(flag, text.lists[&info], help);
        }
        if (!info.metavar.empty()) option->type_name(std::string(info.metavar));
        return option;
      },
      info.field);
}

// Every row with a flag; holes in mm exclude the paper's model parameters, which the hole map sets.
void add_table_flags(CLI::App& app, poreshell::Options& options, FlagText& text) {
  std::map<std::string_view, CLI::Option*> by_name;
  for (const OptionInfo& info : poreshell::option_table())
    if (!info.flag.empty()) by_name[info.name] = add_table_flag(app, info, options, text);
  for (const char* hole : {"hole_diameter", "spacing", "porosity"})
    for (const char* model : {"alpha", "epsilon_m", "dt_h", "phi_bar", "iso"})
      by_name.at(hole)->excludes(by_name.at(model));
}

// "X,Y,Z,R" -> a sphere, "X0,Y0,Z0,X1,Y1,Z1" -> a box; the grading spec; auto|off.
void apply_flag_text(const FlagText& text, poreshell::Options& options) {
  using Options = poreshell::Options;
  for (const auto& [info, list] : text.lists) {
    const auto* spheres = std::get_if<std::vector<poreshell::KeepOutSphere> Options::*>(&info->field);
    const std::size_t count = spheres ? 4 : 6;
    for (const std::string& item : list) {
      const auto v = numbers(item, count);
      if (!v)
        throw UsageError(std::string(info->flag) + " '" + item + "' is not " + std::string(info->metavar) +
                         (spheres ? " (four numbers, mm)" : " (six numbers, mm)"));
      if (spheres)
        (options.**spheres).push_back({{(*v)[0], (*v)[1], (*v)[2]}, (*v)[3]});
      else
        (options.*std::get<std::vector<poreshell::KeepOutBox> Options::*>(info->field))
            .push_back({{(*v)[0], (*v)[1], (*v)[2]}, {(*v)[3], (*v)[4], (*v)[5]}});
    }
  }
  for (const auto& [info, spec] : text.grades)
    if (!spec.empty())
      options.*std::get<std::optional<poreshell::Grade> Options::*>(info->field) =
          poreshell::parse_grade(spec);
  for (const auto& [info, value] : text.switches)
    options.*std::get<bool Options::*>(info->field) = value == "auto";
}

// The input: a shape, a mesh or a point cloud, in --units; returns --shape and --mesh, which others
// exclude.
std::pair<CLI::Option*, CLI::Option*> add_input_flags(CLI::App& app, Command& command) {
  auto* shape =
      app.add_option("--shape", command.shape_name, "surface S: sphere (eq. 3.1) or torus (section 3.2)")
          ->check(CLI::IsMember({"sphere", "torus"}))
          ->capture_default_str();
  auto* mesh =
      app.add_option(
             "--mesh", command.mesh,
             "triangle mesh FILE (STL, OBJ, PLY, OFF, 3MF; holes and open surfaces are fine), fitted to "
             "the unit grid as in section 3.4; coordinates in --units")
          ->type_name("FILE")
          ->excludes(shape);
  app.add_option(
         "--points", command.points,
         "point cloud FILE (.xyz: x y z a line, extra columns ignored; .ply: its vertices), fitted to "
         "the unit grid like --mesh")
      ->type_name("FILE")
      ->excludes(shape)
      ->excludes(mesh);
  app.add_option(
         "--units", command.unit,
         "unit of the input's coordinates (shapes: of the unit cube); lengths on the command line and "
         "all outputs are in mm")
      ->transform(one_of(kUnits))
      ->default_str("mm");
  app.add_option("--radius", command.radius,
                 "size of --shape in mm: sphere radius, torus major radius (default: the unit cube)")
      ->type_name("MM")
      ->check(number_above(0.0, false))
      ->excludes(mesh);
  return {shape, mesh};
}

// What the run writes and shows, its time budget, and a studio project instead of the flags.
void add_run_flags(CLI::App& app, Command& command, CLI::Option* shape, CLI::Option* mesh) {
  app.add_option("--max-seconds", command.max_seconds,
                 "stop a run still computing after this many seconds, with a message and no file")
      ->type_name("S")
      ->check(number_above(0.0, false));
  // This or a view is required, checked after parsing: CLI11 reports a missing required option before an
  // unknown one, which would hide a misspelt flag behind "--output is required".
  app.add_option(
         "-o,--output", command.output,
         "output mesh in mm; the extension picks the format: .stl (binary), .3mf, .obj, .ply (binary); "
         "several --iso levels write OUT-isoC.ext each. Without it, only --html, --png, --holes or "
         "--report are written (to look before printing)")
      ->type_name("OUT.stl");
  app.add_option("--report", command.report, "write the run's JSON report here")->type_name("OUT.json");
  app.add_option("--holes", command.holes_csv,
                 "write the hole table (centre, normal, diameter, circularity, nearest, axis ratio) as CSV")
      ->type_name("OUT.csv");
  app.add_option("--html", command.html,
                 "write the interactive viewer: one self-contained page, opens offline")
      ->type_name("OUT.html");
  app.add_option("--png", command.png, "write a picture of the viewer's view (needs chromium)")
      ->type_name("OUT.png");
  app.add_flag("-q,--quiet", command.quiet,
               "nothing on stdout and no progress: only errors and warnings, on stderr");
  app.add_option("--progress", command.progress,
                 "progress on stderr: auto (a bar per stage with the time left on a terminal, else plain "
                 "lines), bar, plain, or json (one object a line: stage, fraction, seconds, eta)")
      ->check(CLI::IsMember({"auto", "bar", "plain", "json"}))
      ->capture_default_str();
  app.add_option("--project", command.project,
                 "run a studio project (docs/studio.md): its model, settings, keep-outs and painted mask; "
                 "the same file as the studio's Make")
      ->type_name("FILE")
      ->excludes(shape)
      ->excludes(mesh);
}

// False when --help or --version was answered.
bool parse(CLI::App& app, int argc, const char* const* argv) {
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) {  // --help, --version
      app.exit(e);
      return false;
    }
    std::string message = e.what();
    // CLI11's "--wall: At Most 1 required but received 2" for a repeated option.
    if (const auto at = message.find(": At Most 1 required but received"); at != std::string::npos)
      message = message.substr(0, at) + " given more than once; give it once";
    throw UsageError(message);
  }
  if (!app.remaining().empty()) throw UsageError(unknown_argument_message(app, app.remaining().front()));
  return true;
}

}  // namespace

std::optional<Command> parse_command_line(int argc, const char* const* argv) {
  Command command;
  command.arguments.assign(argv, argv + argc);
  CLI::App app{
      "poreshell: porous shells for 3D printing from the nonlocal Cahn-Hilliard equation on a narrow "
      "band (defaults: the sphere of section 3.2)",
      "poreshell"};
  app.set_version_flag("--version", std::string("poreshell ") + poreshell::version());
  app.get_formatter()->column_width(28);
  const auto [shape, mesh] = add_input_flags(app, command);
  FlagText text;
  add_table_flags(app, command.options, text);  // Options' defaults are the paper's section 3.2 values
  add_run_flags(app, command, shape, mesh);
  app.footer("poreshell studio [MODEL] [--port N] ...: the browser front end (poreshell studio --help)");
  app.allow_extras();

  if (!parse(app, argc, argv)) return std::nullopt;
  if (command.output.empty() && command.html.empty() && command.png.empty() && command.holes_csv.empty() &&
      command.report.empty())
    throw UsageError(
        "no output file: give -o OUT.stl for the part, or --html OUT.html to look at it first (or --png, "
        "--holes, --report)");
  apply_flag_text(text, command.options);
  poreshell::validate(command.options);
  return command;
}
