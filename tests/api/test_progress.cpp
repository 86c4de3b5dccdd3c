// Progress and cancellation inside the long stages (issue 18): a run cancelled from another thread at
// random times stops with Error(cancelled) and nothing else, and a mid-size run reports from every stage,
// in order, with fractions that never go back. The gaps between reports are printed, not asserted (the
// machines are noisy); docs/benchmarks.md has the measured ones.

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <map>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "poreshell/poreshell.hpp"

#ifndef PORESHELL_DATA_DIR
#error "PORESHELL_DATA_DIR must name the data folder (see tests/CMakeLists.txt)"
#endif

using namespace poreshell;

namespace {

// The bunny with a reduction, so that every long loop runs: band, multigrid set-up, coarse start, the
// solve, shell sampling, the isosurface, the reduction and the topology check.
Options bunny_options(int resolution) {
  Options o;
  o.resolution = resolution;
  // As far as the bound allows, the default's reduction (issue 49). A budget of 80,000 is no longer
  // within its reach since the sampled check (191,008 the fewest at resolution 90).
  o.max_deviation = 0.2;
  return o;
}

const MeshInput& bunny() {
  static const MeshInput input = load_mesh(std::string(PORESHELL_DATA_DIR) + "/stanford-bunny.obj", Unit::m);
  return input;
}

struct Call {
  std::string stage;
  double fraction, seconds;
};

std::vector<Call> record_run(const Input& input, const Options& options) {
  std::vector<Call> calls;
  perforate(input, options, {[&](const Progress& p) {
              calls.push_back({std::string(p.stage), p.fraction, p.seconds});
            }});
  return calls;
}

}  // namespace

TEST(Progress, CancelledFromAnotherThreadAtRandomTimes) {
  const Options options = bunny_options(90);
  const auto start = std::chrono::steady_clock::now();
  const std::vector<Call> full = record_run(bunny(), options);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::mt19937 random(18);
  std::uniform_real_distribution<double> when(0.0, seconds);
  int cancelled = 0;
  constexpr int kRuns = 8;
  for (int run = 0; run < kRuns; ++run) {
    const double at = when(random);
    std::atomic<bool> cancel{false};
    int calls_after_flag = 0;  // progress calls that began with the flag already set
    std::string stage;
    RunControl control;
    control.cancel = &cancel;
    control.progress = [&](const Progress& p) {
      if (cancel.load()) ++calls_after_flag;
      stage = p.stage;
    };
    std::thread canceller([&] {
      std::this_thread::sleep_for(std::chrono::duration<double>(at));
      cancel = true;
    });
    bool threw = false;
    try {
      const Result result = perforate(bunny(), options, control);
      EXPECT_FALSE(result.outputs.empty());
    } catch (const Error& e) {
      threw = true;
      EXPECT_EQ(e.code(), ErrorCode::cancelled) << e.what();
    }
    canceller.join();
    // check() runs before every report: a report can only see the flag if it was set during that very
    // report, and then the next check throws.
    EXPECT_LE(calls_after_flag, 1) << "the run went on reporting after the flag was set";
    if (calls_after_flag == 1 && stage != "mesh" && stage != "holes") {
      EXPECT_TRUE(threw) << "not cancelled in " << stage;
    }
    if (threw) ++cancelled;
    std::printf("cancel at %.2f s of %.2f s: %s in %s\n", at, seconds, threw ? "cancelled" : "finished",
                stage.c_str());
  }
  EXPECT_GT(cancelled, 0) << "no run was cancelled";
  EXPECT_FALSE(full.empty());
}

TEST(Progress, EveryStageReportsInOrderWithFractionsThatNeverGoBack) {
  const std::vector<Call> calls = record_run(bunny(), bunny_options(150));
  const std::vector<std::string> expected{"input", "band", "solve", "shell", "mesh", "holes"};
  std::vector<std::string> stages;
  std::map<std::string, int> count;
  std::map<std::string, double> longest_gap;
  for (std::size_t i = 0; i < calls.size(); ++i) {
    const Call& c = calls[i];
    if (stages.empty() || stages.back() != c.stage) {
      stages.push_back(c.stage);
      EXPECT_EQ(c.fraction, 0.0) << c.stage << " starts at 0";
    } else {
      EXPECT_GE(c.fraction, calls[i - 1].fraction) << c.stage << " went back";
    }
    EXPECT_GE(c.fraction, 0.0);
    EXPECT_LE(c.fraction, 1.0);
    ++count[c.stage];
    const double next = i + 1 < calls.size() ? calls[i + 1].seconds : c.seconds;
    longest_gap[c.stage] = std::max(longest_gap[c.stage], next - c.seconds);
  }
  ASSERT_EQ(stages, expected);
  for (const std::string& stage : expected) {
    std::printf("%-6s %4d reports, longest gap %.2f s\n", stage.c_str(), count[stage], longest_gap[stage]);
    EXPECT_GE(count[stage], 1) << stage;
  }
  EXPECT_EQ(calls.back().fraction, 1.0);
}
