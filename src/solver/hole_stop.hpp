#pragma once
// The holes rule (docs/solver.md "Stop rules"): a run ends when the hole layout has settled, not when
// the field has stopped changing (the paper's e_c < tol). The layout settles long before e_c is small:
// the last hundreds of steps of a paper-rule run move hole boundaries by hundredths of a voxel. Every
// `every` steps the rule takes the spots {phi > level} on the band; it stops once, over the last
// `window` steps, the hole count has stayed the same, no hole centre has moved more than `max_shift`
// times the holes' mean spacing, and at most `max_flipped` of the band voxels have changed side of the
// level.

#include <cstdint>
#include <deque>
#include <span>
#include <vector>

#include "band/band.hpp"

namespace poreshell {

struct HoleStopOptions {
  double level = 0.0;         // holes are {phi > level}
  int every = 4;              // steps between checks
  int window = 16;            // steps over which the layout must hold (a multiple of `every`)
  double max_shift = 0.05;    // largest centre move over the window, in mean spacings
  double max_flipped = 1e-2;  // share of band voxels that changed side over the window
  // Separated phases span about [-1, 1]: before that the spots are noise. 0: no condition, and no
  // holes at all may count as settled (where no pattern can form).
  double min_spread = 1.0;
};

// What the last check measured.
struct HoleStopCheck {
  int step = -1;
  std::int64_t holes = 0;
  double shift = 0.0;    // largest centre move over the window, in mean spacings (inf: counts differ)
  double flipped = 1.0;  // share of band voxels that changed side over the window
  bool settled = false;
};

class HoleStop {
 public:
  HoleStop(const NarrowBand& band, const HoleStopOptions& options);
  // The state at `step` (0: the initial state; steps must increase). True once the layout has settled;
  // steps between checks return false at once.
  bool settled(int step, std::span<const double> phi);
  // How far the run has come, 0..1, never decreasing: the phases' separation, then the slowest of the
  // conditions (side changes, hole count, centre shift) on its way to its threshold.
  double progress() const { return progress_; }
  const HoleStopCheck& last_check() const { return last_; }
  const HoleStopOptions& options() const { return options_; }

 private:
  struct Snapshot {
    int step = 0;
    std::vector<Vec3> centres;
    std::vector<std::uint8_t> open;  // per band voxel: phi > level
  };
  const NarrowBand& band_;
  HoleStopOptions options_;
  std::deque<Snapshot> history_;  // oldest first, back() the latest
  HoleStopCheck last_;
  double first_flipped_ = 0.0, first_shift_ = 0.0;
  int count_changed_at_ = 0;  // the last step whose hole count differed from the check before
  double progress_ = 0.0;
};

// Largest distance from a point of `a` to its nearest point in `b` (infinity when b is empty).
double largest_nearest_distance(std::span<const Vec3> a, std::span<const Vec3> b);

}  // namespace poreshell
