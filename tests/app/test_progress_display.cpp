// The progress bar's time left (issue 47, item 8): it counts down between updates and follows a lasting
// change of the raw estimate within about its time constant, instead of swinging with each update.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "progress_display.hpp"

namespace {

// The raw estimate jumping between 5 min 40 s and 36 s at every update (ten a second), as the solve's
// uneven share done made it: the shown value moves by little more than the time that passed.
TEST(ProgressDisplay, TheTimeLeftDoesNotSwingWithTheRawEstimate) {
  double shown = -1.0;
  double low = 1e9, high = 0.0;
  for (int update = 0; update < 400; ++update) {
    const double previous = shown;
    shown = smoothed_eta(shown, 0.1, update % 2 == 0 ? 340.0 : 36.0);
    if (update > 0) {
      EXPECT_LT(std::abs(shown - previous), 5.0) << "update " << update;
    }
    if (update >= 300) {
      low = std::min(low, shown);
      high = std::max(high, shown);
    }
  }
  EXPECT_LT(high - low, 10.0) << "settled, the shown value stays within seconds";
}

TEST(ProgressDisplay, TheTimeLeftFollowsALastingChangeAndCountsDown) {
  // An estimate that is right (60 s left, falling with the clock) is shown as it is.
  double shown = smoothed_eta(-1.0, 0.0, 60.0);
  for (int update = 1; update <= 100; ++update) shown = smoothed_eta(shown, 0.1, 60.0 - 0.1 * update);
  EXPECT_NEAR(shown, 50.0, 0.5);
  // A lasting change to 200 s left (falling with the clock from then on) is followed within a few time
  // constants.
  for (int update = 0; update < 400; ++update) shown = smoothed_eta(shown, 0.1, 200.0 - 0.1 * update);
  EXPECT_NEAR(shown, 160.0, 5.0);
  // Unknown raw estimates keep the shown value; the first known one is shown at once.
  EXPECT_EQ(smoothed_eta(42.0, 0.1, -1.0), 42.0);
  EXPECT_EQ(smoothed_eta(-1.0, 0.1, 17.0), 17.0);
}

}  // namespace
