#pragma once
// What the poreshell program prints: per-step progress and warnings on stderr, the run's summary on
// stdout.

#include <span>
#include <string>

#include "poreshell/poreshell.hpp"

// The summary's first lines, before the run: the model's size and what the run will cost, and the
// estimate's warnings (on stdout: a run that then fails still has one error line on stderr).
void print_estimate(const std::string& input_name, const poreshell::Estimate& e);

// A file the run wrote besides the meshes and the report, and what it holds ("hole table").
struct WrittenFile {
  std::string path;  // empty: not written
  const char* what;
};

// The summary: input, grid, band, model, solver, pattern, time, memory, solid, holes and outputs, the
// report and the other files written.
void print_summary(const poreshell::Options& options, const poreshell::Report& r,
                   std::span<const poreshell::Output> outputs, const std::string& report,
                   std::span<const WrittenFile> others);

// What the user should know before printing: an unsteady pattern, clamped grading, no pattern at all.
void print_warnings(const poreshell::Options& options, const poreshell::Report& r);
