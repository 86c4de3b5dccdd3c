#include "solver/hole_stop.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include "pattern/pattern.hpp"

namespace poreshell {

double largest_nearest_distance(std::span<const Vec3> a, std::span<const Vec3> b) {
  if (a.empty()) return 0.0;
  if (b.empty()) return std::numeric_limits<double>::infinity();
  std::vector<Vec3> sorted(b.begin(), b.end());
  std::sort(sorted.begin(), sorted.end(), [](const Vec3& p, const Vec3& q) { return p.x() < q.x(); });
  double largest = 0.0;
  for (const Vec3& p : a) {
    const auto at = std::lower_bound(sorted.begin(), sorted.end(), p.x(),
                                     [](const Vec3& q, double x) { return q.x() < x; });
    double best = std::numeric_limits<double>::infinity();
    for (auto it = at; it != sorted.end() && it->x() - p.x() < best; ++it)
      best = std::min(best, (*it - p).norm());
    for (auto it = at; it != sorted.begin();) {
      --it;
      if (p.x() - it->x() >= best) break;
      best = std::min(best, (*it - p).norm());
    }
    largest = std::max(largest, best);
  }
  return largest;
}

HoleStop::HoleStop(const NarrowBand& band, const HoleStopOptions& options) : band_(band), options_(options) {
  options_.every = std::max(1, options_.every);
  options_.window = std::max(options_.every, options_.window);
}

bool HoleStop::settled(int step, std::span<const double> phi) {
  if (step % options_.every != 0) return false;
  const HoleStats stats = hole_statistics(band_, phi, options_.level);
  Snapshot now;
  now.step = step;
  now.centres.reserve(stats.holes.size());
  for (const BandHole& h : stats.holes) now.centres.push_back(h.centroid);
  now.open.resize(phi.size());
  for (std::size_t v = 0; v < phi.size(); ++v) now.open[v] = phi[v] > options_.level ? 1 : 0;
  const auto [lo, hi] = std::minmax_element(phi.begin(), phi.end());
  const bool separated = phi.empty() || *hi - *lo >= options_.min_spread;

  // The window's start: the oldest snapshot kept, at least `window` steps back.
  while (history_.size() >= 2 && history_[1].step <= step - options_.window) history_.pop_front();
  last_ = {};
  last_.step = step;
  last_.holes = static_cast<std::int64_t>(now.centres.size());
  if (!history_.empty()) {
    const Snapshot& start = history_.front();
    std::size_t flipped = 0;
    for (std::size_t v = 0; v < now.open.size(); ++v) flipped += now.open[v] != start.open[v] ? 1 : 0;
    last_.flipped =
        now.open.empty() ? 0.0 : static_cast<double>(flipped) / static_cast<double>(now.open.size());
    const bool same_count = std::all_of(history_.begin(), history_.end(), [&](const Snapshot& s) {
      return s.centres.size() == now.centres.size();
    });
    const double spacing = stats.spacing_mean > 0.0 ? stats.spacing_mean : 1.0;
    last_.shift = same_count ? std::max(largest_nearest_distance(now.centres, start.centres),
                                        largest_nearest_distance(start.centres, now.centres)) /
                                   spacing
                             : std::numeric_limits<double>::infinity();
    const bool full_window = start.step <= step - options_.window;
    last_.settled = separated && full_window && (!now.centres.empty() || options_.min_spread <= 0.0) &&
                    same_count && last_.shift <= options_.max_shift && last_.flipped <= options_.max_flipped;
  }
  // Progress: a third for the phases' separation, the rest for the slowest of the conditions: the side
  // changes' fall towards max_flipped, and the layout's, half for the count holding over a window and
  // half for the centres' shift falling towards max_shift (both falls in log scale, neither done before
  // the count has held a window). A merge late in the run stalls it; it never goes back, and it is 1
  // only once settled.
  if (!history_.empty() && history_.back().centres.size() != now.centres.size()) count_changed_at_ = step;
  double p = 0.0;
  if (!phi.empty() && options_.min_spread > 0.0) p = std::min(1.0, (*hi - *lo) / options_.min_spread) / 3.0;
  if (separated && !history_.empty()) {
    const auto towards = [](double first, double now_value, double goal) {
      if (now_value <= goal) return 1.0;
      return std::clamp(std::log(first / now_value) / std::log(first / goal), 0.0, 0.99);
    };
    if (first_flipped_ <= 0.0) first_flipped_ = std::max(last_.flipped, 2.0 * options_.max_flipped);
    const double by_flips = towards(first_flipped_, last_.flipped, options_.max_flipped);
    const double held = std::min(1.0, static_cast<double>(step - count_changed_at_) / options_.window);
    double by_layout = 0.5 * held;
    if (std::isfinite(last_.shift)) {
      if (first_shift_ <= 0.0) first_shift_ = std::max(last_.shift, 2.0 * options_.max_shift);
      by_layout += 0.5 * std::min(held, towards(first_shift_, last_.shift, options_.max_shift));
    }
    p = std::min(0.99, (1.0 + 2.0 * std::min(by_flips, by_layout)) / 3.0);
  }
  if (last_.settled) p = 1.0;
  progress_ = std::max(progress_, p);
  history_.push_back(std::move(now));
  return last_.settled;
}

}  // namespace poreshell
