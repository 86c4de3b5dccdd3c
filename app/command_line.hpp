#pragma once
// The command line: argv -> what to read, the options, and what to write.

#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "poreshell/poreshell.hpp"

struct Command {
  poreshell::Options options;
  std::string mesh, points, shape_name = "sphere";  // the input: a mesh file, a point file or a shape
  poreshell::Unit unit = poreshell::Unit::mm;
  double radius = 0.0;  // of the shape, mm (0: the unit cube)
  std::string output, report, holes_csv, html, png;
  std::string project;  // a studio project (docs/studio.md): its model and options replace the flags'

  std::string progress = "auto";
  bool quiet = false;
  double max_seconds = 0.0;            // 0: no time budget
  std::vector<std::string> arguments;  // as given, for the report
};

// A usage error: exit code 2 and "(see poreshell --help)".
class UsageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The parsed and validated command, or nothing when --help or --version was answered. Throws
// UsageError, or poreshell::Error for an option the library refuses.
std::optional<Command> parse_command_line(int argc, const char* const* argv);
