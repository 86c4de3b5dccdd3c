#include "pattern/layout.hpp"

#include <tbb/parallel_for.h>

#include <cmath>
#include <numeric>

#include "geometry/point_tree.hpp"

namespace poreshell {

AreaSamples area_samples(const NarrowBand& band, std::span<const double> zone_weight) {
  AreaSamples s;
  const double h = band.grid().h();
  for (std::size_t v = 0; v < band.size(); ++v) {
    const double area = h * h * std::max(0.0, 1.0 - std::abs(band.distance()[v]) / h);
    if (area <= 0.0 || (!zone_weight.empty() && zone_weight[v] >= 0.5)) continue;
    s.points.push_back(band.closest_point(v));
    s.area.push_back(area);
  }
  return s;
}

std::vector<std::int32_t> nearest_centres(const AreaSamples& samples, std::span<const Vec3> centres) {
  std::vector<std::int32_t> cell(samples.points.size(), -1);
  if (centres.empty()) return cell;
  const PointTree tree(std::vector<Vec3>(centres.begin(), centres.end()));
  tbb::parallel_for(std::size_t{0}, cell.size(), [&](std::size_t i) {
    cell[i] = static_cast<std::int32_t>(tree.nearest(samples.points[i]).first);
  });
  return cell;
}

double cell_area_cv(const AreaSamples& samples, std::span<const Vec3> centres) {
  if (centres.size() < 2) return 0.0;
  const std::vector<std::int32_t> cell = nearest_centres(samples, centres);
  std::vector<double> area(centres.size(), 0.0);
  for (std::size_t i = 0; i < cell.size(); ++i) area[static_cast<std::size_t>(cell[i])] += samples.area[i];
  const double n = static_cast<double>(area.size());
  const double mean = std::accumulate(area.begin(), area.end(), 0.0) / n;
  double var = 0.0;
  for (const double a : area) var += (a - mean) * (a - mean);
  return mean > 0.0 ? std::sqrt(var / n) / mean : 0.0;
}

namespace {

// Each centre moves 1.8 times the way to its centroid: the same fixed points as Lloyd's iteration,
// reached in far fewer iterations (cell-area CV on the sphere, 6 mm at 10 mm, seed 2: 0.0626 after 30
// plain iterations, 0.0609 after 100; over-relaxed 0.0598 after 30, 0.0593 after 100 and 300).
constexpr double kOverRelaxation = 1.8;

}  // namespace

std::vector<Vec3> lloyd_centres(std::vector<Vec3> centres, const AreaSamples& samples, const Surface& surface,
                                int iterations) {
  for (int it = 0; it < iterations && !centres.empty(); ++it) {
    const std::vector<std::int32_t> cell = nearest_centres(samples, centres);
    std::vector<Vec3> sum(centres.size(), Vec3::Zero());
    std::vector<double> area(centres.size(), 0.0);
    for (std::size_t i = 0; i < cell.size(); ++i) {
      const auto c = static_cast<std::size_t>(cell[i]);
      sum[c] += samples.area[i] * samples.points[i];
      area[c] += samples.area[i];
    }
    std::vector<Vec3> moved;
    moved.reserve(centres.size());
    for (std::size_t c = 0; c < centres.size(); ++c) {
      if (area[c] <= 0.0) continue;
      const Vec3 target = centres[c] + kOverRelaxation * (sum[c] / area[c] - centres[c]);
      moved.push_back(surface.closest_point(target).value_or(target));
    }
    centres = std::move(moved);
  }
  return centres;
}

std::vector<double> disc_field(const NarrowBand& band, std::span<const Vec3> centres, double radius,
                               double epsilon, std::span<const double> zone_weight, double mean) {
  std::vector<double> phi(band.size(), -1.0);
  if (!centres.empty()) {
    const PointTree tree(std::vector<Vec3>(centres.begin(), centres.end()));
    const double width = std::sqrt(2.0) * epsilon;
    tbb::parallel_for(std::size_t{0}, band.size(), [&](std::size_t v) {
      phi[v] = std::tanh((radius - tree.nearest(band.closest_point(v)).second) / width);
    });
  }
  const auto free = [&](std::size_t v) { return zone_weight.empty() ? 1.0 : 1.0 - zone_weight[v]; };
  for (std::size_t v = 0; v < zone_weight.size(); ++v) phi[v] = free(v) * phi[v] - zone_weight[v];
  // Sequential sums: the same bytes on any thread count.
  double sum = 0.0, free_sum = 0.0;
  for (std::size_t v = 0; v < phi.size(); ++v) {
    sum += phi[v];
    free_sum += free(v);
  }
  if (free_sum <= 0.0) return phi;
  const double shift = (mean * static_cast<double>(phi.size()) - sum) / free_sum;
  for (std::size_t v = 0; v < phi.size(); ++v) phi[v] += shift * free(v);
  return phi;
}

}  // namespace poreshell
