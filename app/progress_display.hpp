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
  // run_seconds: the estimate of the whole run (0: unknown), for the run's time left beside the stage's.
  explicit ProgressDisplay(ProgressStyle style, double run_seconds = 0.0)
      : style_(style), run_seconds_(run_seconds) {}
  // Called by the run (one call at a time).
  void operator()(const poreshell::Progress& p);
  // After the run (or its failure): ends the bar's last line.
  void finish();

 private:
  void bar(const poreshell::Progress& p);
  void json(const poreshell::Progress& p);

  ProgressStyle style_;
  double run_seconds_ = 0.0;
  std::string stage_;         // the stage being shown
  double stage_start_ = 0.0;  // run seconds at its start
  double eta_ = -1.0;         // the stage's time left as shown (smoothed; negative: not known yet)
  double eta_at_ = 0.0;       // run seconds when eta_ was last updated
  bool line_open_ = false;    // a bar line without its newline yet
  std::chrono::steady_clock::time_point last_draw_{};
};

// Seconds left in a stage from the share done and the time it took (negative: not known yet).
double eta_seconds(double fraction, double stage_seconds);

// The time left as shown: the previous value counted down by the seconds since, moved towards the new
// raw estimate with a time constant of `tau` seconds. The solve's share done is uneven (the holes rule
// settles in jumps), so the raw estimate swung from 5 min 40 s to 36 s and back (issue 47); this one
// takes about tau to follow a lasting change. Negative values mean "not known".
double smoothed_eta(double previous, double seconds_since, double raw, double tau = 10.0);
