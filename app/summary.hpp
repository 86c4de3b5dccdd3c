#pragma once
// What the poreshell program prints: per-step progress on stderr and the run's summary on stdout.

#include <chrono>
#include <string>

#include "pipeline/pipeline.hpp"

// Progress: the first step, every tenth, and every step where the energy was evaluated.
void print_progress(const poreshell::StepProgress& p, std::chrono::steady_clock::time_point start);

// The summary: input, grid, band, model, solver, pattern, time, memory, solid, holes and outputs.
void print_summary(const poreshell::PipelineConfig& c, const poreshell::PipelineResult& r,
                   const std::string& report);
