#include "pattern/pattern.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <numbers>

namespace poreshell {

std::vector<std::int32_t> label_spots(const NarrowBand& band, std::span<const double> phi, double level) {
  const std::size_t n = band.size();
  std::vector<std::int32_t> label(n, -1);
  std::vector<std::size_t> stack;
  std::int32_t next = 0;
  for (std::size_t seed = 0; seed < n; ++seed) {
    if (label[seed] >= 0 || !(phi[seed] > level)) continue;
    label[seed] = next;
    stack.push_back(seed);
    while (!stack.empty()) {
      const std::size_t v = stack.back();
      stack.pop_back();
      for (int k = 0; k < NarrowBand::kNeighbors; ++k) {
        const auto nb = static_cast<std::size_t>(band.neighbor(v, k));
        if (nb < n && label[nb] < 0 && phi[nb] > level) {
          label[nb] = next;
          stack.push_back(nb);
        }
      }
    }
    ++next;
  }
  return label;
}

namespace {

double mean_of(const std::vector<double>& x) {
  double sum = 0.0;
  for (double v : x) sum += v;
  return x.empty() ? 0.0 : sum / static_cast<double>(x.size());
}

double cv_of(const std::vector<double>& x) {
  const double m = mean_of(x);
  if (x.size() < 2 || m == 0.0) return 0.0;
  double var = 0.0;
  for (double v : x) var += (v - m) * (v - m);
  return std::sqrt(var / static_cast<double>(x.size())) / m;
}

std::vector<double> nearest_neighbour_distances(std::vector<Vec3> points);

}  // namespace

std::int64_t close_small_spots(const NarrowBand& band, std::span<double> phi, double level,
                               double min_diameter) {
  const std::vector<std::int32_t> label = label_spots(band, phi, level);
  std::vector<double> area;
  for (std::size_t v = 0; v < label.size(); ++v) {
    if (label[v] < 0) continue;
    const auto l = static_cast<std::size_t>(label[v]);
    if (l >= area.size()) area.resize(l + 1, 0.0);
    area[l] += band.surface_area(v);
  }
  const double least_area = std::numbers::pi * min_diameter * min_diameter / 4.0;
  std::int64_t closed = 0;
  for (const double a : area) closed += a < least_area ? 1 : 0;
  for (std::size_t v = 0; v < label.size(); ++v)
    if (label[v] >= 0 && area[static_cast<std::size_t>(label[v])] < least_area) phi[v] = -1.0;
  return closed;
}

namespace {

// Area-weighted second moments of spots' closest points on the surface.
struct SpotMoments {
  double w = 0.0;
  Vec3 sum = Vec3::Zero();
  Eigen::Matrix3d outer = Eigen::Matrix3d::Zero();

  void add(double weight, const Vec3& p) {
    w += weight;
    sum += weight * p;
    outer += weight * p * p.transpose();
  }
  Vec3 mean() const { return sum / w; }
  // Ascending: the normal's, the minor axis's, the major axis's variance.
  Vec3 variances() const {
    const Vec3 m = mean();
    const Eigen::Matrix3d covariance = outer / w - m * m.transpose();
    return Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(covariance, Eigen::EigenvaluesOnly).eigenvalues();
  }
  double axis_ratio() const {
    const Vec3 lambda = variances();
    return lambda[2] > 0.0 ? std::sqrt(std::max(lambda[1], 0.0) / lambda[2]) : 1.0;
  }
};

}  // namespace

OblongSpots round_oblong_spots(const NarrowBand& band, std::span<double> phi, double level,
                               const OblongRule& rule, const std::function<bool(const Vec3&)>& kept) {
  const std::vector<std::int32_t> label = label_spots(band, phi, level);
  std::vector<SpotMoments> spots;
  for (std::size_t v = 0; v < label.size(); ++v) {
    if (label[v] < 0) continue;
    const auto l = static_cast<std::size_t>(label[v]);
    if (l >= spots.size()) spots.resize(l + 1);
    spots[l].add(band.surface_area(v), band.closest_point(v));
  }
  // An oblong spot is cut to a disc about its centre: of its own area's radius sqrt(a b) where that
  // leaves it round (the ellipse's ends trimmed; a and b its semi-axes, 2 sqrt(variance) for a uniform
  // ellipse), else of its minor semi-axis b, the inscribed disc. phi is lowered to a ramp through the
  // level at that radius, with the slope of the equation's own tanh profile there, so that the new edge
  // is as smooth as the others.
  constexpr std::size_t kRadii = 2;
  std::vector<std::array<double, kRadii>> radii(spots.size(), {0.0, 0.0});
  std::vector<char> oblong(spots.size(), 0);
  for (std::size_t l = 0; l < spots.size(); ++l) {
    const SpotMoments& m = spots[l];
    if (!(m.w > 0.0) || !(m.axis_ratio() < rule.min_axis_ratio)) continue;
    // `kept` (a walk over the open boundary) asked of the few oblong spots only, not of every spot.
    if (kept && kept(m.mean())) continue;
    oblong[l] = 1;
    const Vec3 lambda = m.variances().cwiseMax(0.0);
    radii[l] = {2.0 * std::sqrt(std::sqrt(lambda[1] * lambda[2])), 2.0 * std::sqrt(lambda[1])};
  }
  const double slope = (1.0 - level * level) / (std::numbers::sqrt2 * rule.epsilon);
  const auto cut = [&](double value, double radius, double r) {
    return std::max(-1.0, std::min(value, level + slope * (radius - r)));
  };
  std::vector<std::array<SpotMoments, kRadii>> left(spots.size());
  for (std::size_t v = 0; v < label.size(); ++v) {
    if (label[v] < 0 || !oblong[static_cast<std::size_t>(label[v])]) continue;
    const auto l = static_cast<std::size_t>(label[v]);
    const Vec3 p = band.closest_point(v);
    const double r = (p - spots[l].mean()).norm();
    for (std::size_t k = 0; k < kRadii; ++k)
      if (cut(phi[v], radii[l][k], r) > level) left[l][k].add(band.surface_area(v), p);
  }
  // What is left must be a hole as wide as the small-hole rule asks, and round (a banana's or a
  // figure-eight's centre lies off its spot: the cut leaves a sliver or two pieces); else it is closed.
  const double least_area = std::numbers::pi * rule.min_diameter * rule.min_diameter / 4.0;
  OblongSpots result;
  std::vector<double> radius(spots.size(), -1.0);  // the cut's; -1 closes the spot
  for (std::size_t l = 0; l < spots.size(); ++l) {
    if (!oblong[l]) continue;
    for (std::size_t k = 0; k < kRadii && radius[l] < 0.0; ++k) {
      const SpotMoments& m = left[l][k];
      if (m.w >= least_area && m.axis_ratio() >= rule.min_axis_ratio) radius[l] = radii[l][k];
    }
    ++(radius[l] < 0.0 ? result.closed : result.rounded);
  }
  for (std::size_t v = 0; v < label.size(); ++v) {
    if (label[v] < 0 || !oblong[static_cast<std::size_t>(label[v])]) continue;
    const auto l = static_cast<std::size_t>(label[v]);
    phi[v] =
        radius[l] < 0.0 ? -1.0 : cut(phi[v], radius[l], (band.closest_point(v) - spots[l].mean()).norm());
  }
  return result;
}

HoleStats hole_statistics(const NarrowBand& band, std::span<const double> phi, double level,
                          const std::function<bool(const Vec3&)>& counted) {
  const std::vector<std::int32_t> label = label_spots(band, phi, level);
  const double h = band.grid().h();
  std::vector<BandHole> all;
  std::vector<std::int64_t> voxels;
  std::vector<Vec3> closest_sum, reference;  // per hole: sum of closest points; the normal's orientation
  double open_area = 0.0, total_area = 0.0;
  for (std::size_t v = 0; v < label.size(); ++v) {
    const double area = band.surface_area(v);
    total_area += area;
    if (label[v] < 0) continue;
    const auto l = static_cast<std::size_t>(label[v]);
    if (l >= all.size()) {
      all.resize(l + 1);
      voxels.resize(l + 1, 0);
      closest_sum.resize(l + 1, Vec3::Zero());
      reference.resize(l + 1, Vec3::Zero());
    }
    const Vec3 x = band.grid().position(band.voxels()[v]);
    const Vec3 cp = band.closest_point(v);
    all[l].centroid += x;
    all[l].area += area;
    closest_sum[l] += cp;
    // x - cp points away from the surface; the distance's sign turns it outward where there is an
    // inside. On an open surface the two sides are aligned with the hole's first clear offset.
    Vec3 offset = band.distance()[v] < 0.0 ? Vec3(cp - x) : Vec3(x - cp);
    if (reference[l].isZero() && offset.norm() > 0.25 * h) reference[l] = offset;
    if (offset.dot(reference[l]) < 0.0) offset = -offset;
    all[l].normal += offset;
    ++voxels[l];
    open_area += area;
  }
  HoleStats s;
  s.porosity = total_area > 0.0 ? open_area / total_area : 0.0;
  std::vector<Vec3> centroids;
  for (std::size_t l = 0; l < all.size(); ++l) {
    BandHole& hole = all[l];
    hole.centroid /= static_cast<double>(voxels[l]);
    hole.diameter = 2.0 * std::sqrt(hole.area / std::numbers::pi);
    const double length = hole.normal.norm();
    hole.normal = length > 0.0 ? Vec3(hole.normal / length) : Vec3::Zero();
    const Vec3 on_surface = closest_sum[l] / static_cast<double>(voxels[l]);
    hole.centre = hole.centroid - (hole.centroid - on_surface).dot(hole.normal) * hole.normal;
    centroids.push_back(hole.centroid);
  }
  const std::vector<double> nearest =
      centroids.size() >= 2 ? nearest_neighbour_distances(centroids) : std::vector<double>(all.size(), 0.0);
  std::vector<double> diameters, spacings;
  for (std::size_t l = 0; l < all.size(); ++l) {
    if (counted && !counted(all[l].centroid)) continue;
    if (centroids.size() >= 2) all[l].nearest = nearest[l];
    s.holes.push_back(all[l]);
    diameters.push_back(all[l].diameter);
    if (centroids.size() >= 2) spacings.push_back(nearest[l]);
  }
  s.diameter_mean = mean_of(diameters);
  s.diameter_cv = cv_of(diameters);
  s.spacing_mean = mean_of(spacings);
  s.spacing_cv = cv_of(spacings);
  return s;
}

namespace {

// Nearest-neighbour distance of each point: points sorted along x, each scans outwards both ways
// and stops where the x gap alone exceeds its best distance (about n sqrt(n) on a surface).
// returned in the input's order.
std::vector<double> nearest_neighbour_distances(std::vector<Vec3> points) {
  std::vector<std::size_t> order(points.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return points[a].x() < points[b].x() || (points[a].x() == points[b].x() && a < b);
  });
  const auto n = static_cast<std::ptrdiff_t>(points.size());
  std::vector<double> best(points.size(), std::numeric_limits<double>::infinity());
  for (std::ptrdiff_t i = 0; i < n; ++i) {
    double& b = best[order[static_cast<std::size_t>(i)]];
    const Vec3& p = points[order[static_cast<std::size_t>(i)]];
    for (std::ptrdiff_t step : {-1, 1})
      for (std::ptrdiff_t j = i + step; j >= 0 && j < n; j += step) {
        const Vec3& q = points[order[static_cast<std::size_t>(j)]];
        if (std::abs(q.x() - p.x()) >= b) break;
        b = std::min(b, (q - p).norm());
      }
  }
  return best;
}

}  // namespace

SpotStats spot_statistics(const NarrowBand& band, std::span<const double> phi, double level) {
  const std::vector<std::int32_t> label = label_spots(band, phi, level);
  SpotStats s;
  std::int64_t inside = 0;
  for (std::int32_t l : label) {
    if (l < 0) continue;
    if (static_cast<std::size_t>(l) >= s.sizes.size()) s.sizes.resize(static_cast<std::size_t>(l) + 1, 0);
    ++s.sizes[static_cast<std::size_t>(l)];
    ++inside;
  }
  s.count = static_cast<std::int64_t>(s.sizes.size());
  s.area_fraction = band.size() ? static_cast<double>(inside) / static_cast<double>(band.size()) : 0.0;
  if (s.count == 0) return s;
  const std::vector<double> sizes(s.sizes.begin(), s.sizes.end());
  s.mean_size = mean_of(sizes);
  s.size_cv = cv_of(sizes);

  std::vector<Vec3> centroids(s.sizes.size(), Vec3::Zero());
  for (std::size_t v = 0; v < label.size(); ++v)
    if (label[v] >= 0) {
      const Coord c = band.voxels()[v];
      centroids[static_cast<std::size_t>(label[v])] += Vec3(c.i, c.j, c.k);
    }
  for (std::size_t l = 0; l < centroids.size(); ++l) centroids[l] /= static_cast<double>(s.sizes[l]);
  if (centroids.size() >= 2) {
    const std::vector<double> nearest = nearest_neighbour_distances(std::move(centroids));
    s.spacing_mean = mean_of(nearest);
    s.spacing_cv = cv_of(nearest);
  }
  return s;
}

}  // namespace poreshell
