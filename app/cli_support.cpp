#include "cli_support.hpp"

#include "command_line.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <utility>

#include "poreshell/option_table.hpp"
#include "poreshell/viewer.hpp"

namespace fs = std::filesystem;

// The library names options by their API names in backquotes (`hole_diameter`); here they are flags.
std::string with_flags(std::string message) {
  for (std::size_t open = message.find('`'); open != std::string::npos; open = message.find('`', open)) {
    const std::size_t close = message.find('`', open + 1);
    if (close == std::string::npos) break;
    const std::string name = message.substr(open + 1, close - open - 1);
    const poreshell::OptionInfo* info = poreshell::find_option(name);
    std::string flag;
    if (info && !info->flag.empty()) {
      flag = info->flag;
    } else if (name == "radius_mm") {  // the shape's size, an input rather than an option
      flag = "--radius";
    } else {
      flag = "--" + name;
      for (char& ch : flag)
        if (ch == '_') ch = '-';
    }
    message.replace(open, close - open + 1, flag);
    open += flag.size();
  }
  return message;
}

// Like CLI::PositiveNumber / NonNegativeNumber, but with a message that states the rule instead of
// printing the range up to DBL_MAX.
CLI::Validator number_above(double low, bool inclusive) {
  const std::string rule = inclusive ? ">= " : "> ";
  return CLI::Validator(
      [=](std::string& text) -> std::string {
        double v = 0.0;
        if (!CLI::detail::lexical_cast(text, v) || !std::isfinite(v) || (inclusive ? v < low : v <= low))
          return fmt::format("must be a number {}{:g}, got '{}'", rule, low, text);
        return {};
      },
      "", "");
}

// "X,Y,Z,..." with exactly `count` numbers, or nothing.
std::optional<std::vector<double>> numbers(const std::string& text, std::size_t count) {
  std::vector<double> values;
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = text.find(',', start);
    double v = 0.0;
    if (!CLI::detail::lexical_cast(text.substr(start, comma - start), v) || !std::isfinite(v))
      return std::nullopt;
    values.push_back(v);
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  if (values.size() != count) return std::nullopt;
  return values;
}

namespace {

// "--resolutoin" -> "--resolution": the flag nearest by edit distance, if it is near enough.
std::size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t above = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = above;
    }
  }
  return row[b.size()];
}

}  // namespace

std::string unknown_argument_message(const CLI::App& app, const std::string& argument) {
  std::string message = "unknown argument '" + argument + "'";
  if (argument.rfind("--", 0) != 0) return message;
  const std::string name = argument.substr(0, argument.find('='));
  std::string best;
  std::size_t best_distance = std::max<std::size_t>(2, name.size() / 3) + 1;  // a third of it, at least 2
  for (const CLI::Option* option : app.get_options())
    for (const std::string& long_name : option->get_lnames()) {
      const std::size_t d = edit_distance(name, "--" + long_name);
      if (d < best_distance) {
        best_distance = d;
        best = "--" + long_name;
      }
    }
  if (!best.empty()) message += "; did you mean " + best + "?";
  return message;
}

// The report's name of an input: its file, or the shape.
std::string input_name(const poreshell::Input& input) {
  if (const auto* m = std::get_if<poreshell::MeshInput>(&input)) return m->name;
  if (const auto* p = std::get_if<poreshell::PointsInput>(&input)) return p->name;
  return std::get<poreshell::ShapeInput>(input).kind == poreshell::ShapeKind::torus ? "torus" : "sphere";
}

// The run's estimate, its warnings naming flags.
poreshell::Estimate estimate_with_flags(const poreshell::Prepared& prepared) {
  poreshell::Estimate e = poreshell::estimate(prepared);
  for (std::string& warning : e.warnings) warning = with_flags(warning);
  return e;
}

namespace {

// The file a path names: links, "." and ".." resolved in the part that exists.
fs::path resolved(const std::string& path) {
  std::error_code ec;
  fs::path p = fs::weakly_canonical(fs::absolute(path, ec), ec);
  return ec ? fs::absolute(path).lexically_normal() : p;
}

bool same_file(const std::string& a, const std::string& b) {
  if (resolved(a) == resolved(b)) return true;
  std::error_code ec;
  return fs::equivalent(a, b, ec) && !ec;  // hard links
}

}  // namespace

void check_output_paths(const Command& command) {
  const poreshell::Options& options = command.options;
  const bool several = options.iso.size() > 1 && options.hole_diameter <= 0.0 && options.spacing <= 0.0 &&
                       options.porosity <= 0.0;
  std::vector<std::pair<std::string, std::string>> outputs;  // flag, path
  if (!command.output.empty()) {
    poreshell::check_mesh_path(command.output);
    const std::size_t levels = several ? options.iso.size() : 1;
    for (std::size_t i = 0; i < levels; ++i)
      outputs.emplace_back(
          "-o",
          poreshell::output_path_for_level(command.output, several ? options.iso[i] : 0.0, several).string());
  }
  for (const auto& [flag, path] : {std::pair<const char*, const std::string&>{"--report", command.report},
                                   {"--holes", command.holes_csv},
                                   {"--html", command.html},
                                   {"--png", command.png}})
    if (!path.empty()) {
      poreshell::check_output_path(path);
      outputs.emplace_back(flag, path);
    }
  const std::string& input = !command.mesh.empty() ? command.mesh : command.points;
  const char* input_flag = !command.mesh.empty() ? "--mesh" : "--points";
  for (std::size_t i = 0; i < outputs.size(); ++i) {
    const auto& [flag, path] = outputs[i];
    if (!input.empty() && same_file(path, input))
      throw UsageError(
          fmt::format("{} '{}' is the input file ({} '{}'): it would be overwritten; give {} another path",
                      flag, path, input_flag, input, flag));
    for (std::size_t j = 0; j < i; ++j)
      if (same_file(path, outputs[j].second))
        throw UsageError(
            fmt::format("{} '{}' and {} '{}' are the same file: one would overwrite the other; "
                        "give each output its own path",
                        outputs[j].first, outputs[j].second, flag, path));
  }
}

int usage_error(const std::string& message) {
  fmt::print(stderr, "poreshell: error: {} (see poreshell --help)\n", message);
  return kExitUsage;
}

// The viewer page and its picture; a picture alone is taken of a page in a temporary file.
void save_views(const std::string& html, const std::string& png, const poreshell::Result& result,
                const poreshell::Options& options, const poreshell::Input& input) {
  if (html.empty() && png.empty()) return;
  const fs::path page = !html.empty() ? fs::path(html) : fs::path(png).replace_extension(".tmp-view.html");
  poreshell::save_html(page, result, options, &input);
  if (png.empty()) return;
  try {
    poreshell::save_png(page, png);
  } catch (...) {
    if (html.empty()) fs::remove(page);
    throw;
  }
  if (html.empty()) fs::remove(page);
}
