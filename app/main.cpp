// poreshell: the command-line front end of the library's public API. Flags -> poreshell::Options and
// an input -> perforate() -> files, summary and report. Everything else lives in the library.

#include <fmt/core.h>
#include <signal.h>
#include <unistd.h>

#include <array>
#include <atomic>
#include <chrono>
#include <exception>
#include <filesystem>
#include <string>
#include <vector>

#include "cli_support.hpp"
#include "command_line.hpp"
#include "poreshell/poreshell.hpp"
#include "progress_display.hpp"
#include "project.hpp"
#include "studio.hpp"
#include "summary.hpp"

namespace {

namespace fs = std::filesystem;
using poreshell::Error;

std::atomic<bool> writing{false};  // set once the first output file is begun

// SIGINT and SIGTERM end the program at once: a run writes nothing until it is done, and a write in
// progress leaves only its temporary, which the handler removes (async-signal-safe calls only).
extern "C" void on_interrupt(int signal_number) {
  poreshell::remove_partial_files();
  static constexpr char before[] = "\nporeshell: error: interrupted; nothing was written\n";
  static constexpr char during[] =
      "\nporeshell: error: interrupted while writing: the file being written was removed, the files "
      "already complete were kept; run again for the rest\n";
  const bool late = writing.load();
  [[maybe_unused]] const auto written =
      ::write(STDERR_FILENO, late ? during : before, (late ? sizeof during : sizeof before) - 1);
  ::_exit(128 + signal_number);
}

// A signal ignored when the program starts (SIGINT under nohup or `cmd &`) stays ignored.
void stop_on_interrupt() {
  struct sigaction action {};
  action.sa_handler = on_interrupt;
  sigemptyset(&action.sa_mask);
  sigaddset(&action.sa_mask, SIGINT);
  sigaddset(&action.sa_mask, SIGTERM);
  for (const int signal_number : {SIGINT, SIGTERM}) {
    struct sigaction previous {};
    ::sigaction(signal_number, nullptr, &previous);
    if (previous.sa_handler != SIG_IGN) ::sigaction(signal_number, &action, nullptr);
  }
}

int run(int argc, char** argv) {
  stop_on_interrupt();
  const std::optional<Command> parsed = parse_command_line(argc, argv);
  if (!parsed) return 0;  // --help, --version
  Command command = *parsed;
  std::optional<studio::Project> project;
  if (!command.project.empty()) {
    project = studio::load_project(command.project);
    command.options = project->options;
  }
  const poreshell::Options& options = command.options;
  const std::string &output = command.output, &report = command.report, &holes_csv = command.holes_csv,
                    &html = command.html, &png = command.png, &mesh = command.mesh, &points = command.points;

  // Fail before the (possibly minutes long) run rather than after it.
  const bool several = options.iso.size() > 1 && options.hole_diameter <= 0.0 && options.spacing <= 0.0 &&
                       options.porosity <= 0.0;
  check_output_paths(command);

  poreshell::Input input;
  if (project) {
    input = std::move(project->input);
  } else if (!mesh.empty()) {
    std::vector<std::string> fields;
    if (!options.keep_out_mask.empty()) fields.push_back(options.keep_out_mask);
    if (options.grade && options.grade->kind == poreshell::Grade::Kind::field)
      fields.push_back(options.grade->field);
    input = poreshell::load_mesh(mesh, command.unit, fields);
  } else if (!points.empty()) {
    input = poreshell::load_points(points, command.unit);
  } else {
    input = poreshell::ShapeInput{
        command.shape_name == "torus" ? poreshell::ShapeKind::torus : poreshell::ShapeKind::sphere,
        command.radius, command.unit};
  }
  // The estimate runs even when quiet: its checks refuse a run that cannot fit before it starts. The run
  // starts from the same prepared input (placing a 70k-triangle scan twice cost a tenth of a second).
  const poreshell::Prepared prepared = poreshell::prepare(input, options);
  const poreshell::Estimate cost = estimate_with_flags(prepared);
  if (!command.quiet) print_estimate(input_name(input), cost);
  ProgressDisplay display(progress_style(command.progress, command.quiet), cost.seconds);
  poreshell::RunControl control;
  control.progress = [&display](const poreshell::Progress& p) { display(p); };
  control.max_seconds = command.max_seconds;
  poreshell::Result result = [&] {
    try {
      return poreshell::perforate(prepared, control);
    } catch (...) {
      display.finish();
      throw;
    }
  }();
  display.finish();

  // Every mesh was built and checked before any is written; each is written to a temporary name and
  // renamed.
  poreshell::Report& r = result.report;
  r.command_line = command.arguments;
  writing = true;
  const auto start_write = std::chrono::steady_clock::now();
  for (std::size_t i = 0; i < result.outputs.size() && !output.empty(); ++i) {
    const fs::path path = poreshell::output_path_for_level(output, result.outputs[i].iso, several);
    poreshell::save_mesh(path, result.outputs[i]);
    r.outputs[i].path = path.string();
  }
  const double write_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start_write).count();
  r.seconds.mesh += write_seconds;
  r.seconds.total += write_seconds;
  if (!holes_csv.empty()) poreshell::save_holes_csv(holes_csv, result.outputs.front().holes);
  if (!report.empty()) poreshell::save_report(report, r, result.outputs);
  save_views(html, png, result, options, input);

  if (!command.quiet)
    print_summary(
        options, r, result.outputs, report,
        std::array<WrittenFile, 3>{{{holes_csv, "hole table"}, {html, "viewer"}, {png, "picture"}}});
  // Quiet, the estimate's warnings (a keep-out that touches nothing, a wall thinner than printers make)
  // are said after the run, on stderr with the run's own.
  if (command.quiet)
    for (const std::string& warning : cost.warnings) fmt::print(stderr, "poreshell: warning: {}\n", warning);
  print_warnings(options, r);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    if (argc > 1 && std::string_view(argv[1]) == "studio") return studio_main(argc - 1, argv + 1);
    return run(argc, argv);
  } catch (const Error& e) {  // its message says what to fix
    fmt::print(stderr, "poreshell: error: {}\n", with_flags(e.what()));
  } catch (const UsageError& e) {
    return usage_error(e.what());
  } catch (const std::exception& e) {
    fmt::print(stderr, "poreshell: error: {}\n", e.what());
  } catch (...) {
    fmt::print(stderr, "poreshell: error: unknown failure\n");
  }
  return kExitFailure;
}
