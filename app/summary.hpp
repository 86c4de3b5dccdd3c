#pragma once
// What the poreshell program prints: per-step progress and warnings on stderr, the run's summary on
// stdout.

#include <span>
#include <string>

#include "poreshell/poreshell.hpp"

// Progress: the solve's first step, every tenth, and every step where the energy was evaluated.
void print_progress(const poreshell::Progress& p);

// The summary: input, grid, band, model, solver, pattern, time, memory, solid, holes and outputs.
void print_summary(const poreshell::Options& options, const poreshell::Report& r,
                   std::span<const poreshell::Output> outputs, const std::string& report);

// What the user should know before printing: an unsteady pattern, clamped grading, no pattern at all.
void print_warnings(const poreshell::Options& options, const poreshell::Report& r);
