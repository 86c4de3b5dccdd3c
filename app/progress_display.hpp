#pragma once
// The program's progress on stderr (--progress): on a terminal one line per stage, redrawn in place
// with a bar, the percentage and an estimate of the time left; elsewhere plain lines (the solve's first
// step, every tenth and every step with an energy); or one JSON object a line for programs.

#include <chrono>
#include <string>

#include "poreshell/poreshell.hpp"

enum class ProgressStyle { none, bar, plain, json };

// --progress auto|bar|plain|json (auto: a bar when stderr is a terminal, else plain); --quiet gives none.
ProgressStyle progress_style(const std::string& flag, bool quiet);

class ProgressDisplay {
 public:
  explicit ProgressDisplay(ProgressStyle style) : style_(style) {}
  // Called by the run (one call at a time).
  void operator()(const poreshell::Progress& p);
  // After the run (or its failure): ends the bar's last line.
  void finish();

 private:
  void bar(const poreshell::Progress& p);
  void json(const poreshell::Progress& p);

  ProgressStyle style_;
  std::string stage_;         // the stage being shown
  double stage_start_ = 0.0;  // run seconds at its start
  bool line_open_ = false;    // a bar line without its newline yet
  std::chrono::steady_clock::time_point last_draw_{};
};

// Seconds left in a stage from the share done and the time it took (negative: not known yet).
double eta_seconds(double fraction, double stage_seconds);
