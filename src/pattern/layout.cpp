#include "pattern/layout.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <numeric>

#include "core/disjoint_sets.hpp"
#include "geometry/point_tree.hpp"

namespace poreshell {

AreaSamples area_samples(const NarrowBand& band, std::span<const double> zone_weight, double margin) {
  AreaSamples s;
  std::vector<Vec3> zone;
  for (std::size_t v = 0; v < band.size(); ++v) {
    const double area = band.surface_area(v);
    if (area <= 0.0) continue;
    if (!zone_weight.empty() && zone_weight[v] >= 0.5) {
      zone.push_back(band.closest_point(v));
      continue;
    }
    s.points.push_back(band.closest_point(v));
    s.area.push_back(area);
    s.voxel.push_back(static_cast<std::int32_t>(v));
  }
  if (zone.empty() || margin <= 0.0) return s;
  const PointTree tree(std::move(zone));
  std::vector<char> keep(s.points.size());
  tbb::parallel_for(std::size_t{0}, keep.size(),
                    [&](std::size_t i) { keep[i] = tree.nearest(s.points[i]).second >= margin; });
  AreaSamples kept;
  for (std::size_t i = 0; i < keep.size(); ++i)
    if (keep[i]) {
      kept.points.push_back(s.points[i]);
      kept.area.push_back(s.area[i]);
      kept.voxel.push_back(s.voxel[i]);
    }
  return kept;
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

// The equation's own hole density: the surface's area per hole over the spacing squared (the spacing is
// the mean distance to the nearest hole). Sphere of radius 50 mm, 6 mm holes at 10 mm, the equation's
// layout: 297 holes on 31,416 mm^2 -> 1.058 (a perfect hexagonal packing would give 0.866).
constexpr double kAreaPerHole = 1.058;

// The equation keeps its spots off solid zones (rims, keep-outs, thin parts): the layout leaves this
// much (times the spacing) of free surface around them. On the bunny (8 mm holes at 14 mm, its thin
// ears and base holes in zones), 11 of 202 discs at 0 vanished as the equation settled them and the
// survivors moved 0.63 mm on average; at 0.15: 6 of 190, moved 0.31 mm; at 0.25 and 0.35, 7 again
// (the count fell to 179 and 169, off the equation's 191).
constexpr double kZoneMargin = 0.15;

// Lloyd's iterations from the farthest-point start: the sphere's cell-area CV (6 mm at 10 mm) settles
// well within them (docs/solver.md "Layout").
constexpr int kLloydIterations = 60;

// Each sample's nearest centre as nearest_centres gives it, searched first among the centre nearest it
// before (`previous`, indices into `centres`; empty: none) and that centre's kCandidates nearest: a
// centre off that list is at least `reach` (the list's last distance) from the previous one, so at least
// reach - |x - previous| from the sample x; where that is not more than the best on the list, the tree
// decides. The same cells as nearest_centres, several times faster once the centres move little.
constexpr std::size_t kCandidates = 12;

std::vector<std::int32_t> nearest_centres_near(const AreaSamples& samples, std::span<const Vec3> centres,
                                               std::span<const std::int32_t> previous) {
  if (previous.size() != samples.points.size() || centres.size() <= kCandidates)
    return nearest_centres(samples, centres);
  const PointTree tree(std::vector<Vec3>(centres.begin(), centres.end()));
  const std::size_t k = kCandidates + 1;  // the centre itself and its kCandidates nearest
  std::vector<std::int32_t> list(centres.size() * k);
  std::vector<double> reach(centres.size());
  tbb::parallel_for(std::size_t{0}, centres.size(), [&](std::size_t c) {
    const std::vector<std::size_t> near = tree.k_nearest(centres[c], k);
    for (std::size_t j = 0; j < k; ++j) list[c * k + j] = static_cast<std::int32_t>(near[j]);
    reach[c] = (centres[near.back()] - centres[c]).norm();
  });
  std::vector<std::int32_t> cell(samples.points.size(), -1);
  tbb::parallel_for(std::size_t{0}, cell.size(), [&](std::size_t i) {
    const Vec3& x = samples.points[i];
    const auto p = static_cast<std::size_t>(previous[i]);
    double best_d2 = std::numeric_limits<double>::infinity();
    std::int32_t best = -1;
    for (std::size_t j = p * k; j < (p + 1) * k; ++j) {
      const double d2 = (centres[static_cast<std::size_t>(list[j])] - x).squaredNorm();
      if (d2 < best_d2 || (d2 == best_d2 && list[j] < best)) {
        best_d2 = d2;
        best = list[j];
      }
    }
    // A relative 1e-9 of slack for the rounding of the distances.
    const bool sure =
        std::sqrt(best_d2) * (1.0 + 1e-9) < reach[p] - (centres[p] - x).norm() - 1e-9 * reach[p];
    cell[i] = sure ? best : static_cast<std::int32_t>(tree.nearest(x).first);
  });
  return cell;
}

}  // namespace

std::vector<Vec3> lloyd_centres(std::vector<Vec3> centres, const AreaSamples& samples, const Surface& surface,
                                int iterations) {
  std::vector<std::int32_t> cell;
  for (int it = 0; it < iterations && !centres.empty(); ++it) {
    cell = nearest_centres_near(samples, centres, cell);
    std::vector<Vec3> sum(centres.size(), Vec3::Zero());
    std::vector<double> area(centres.size(), 0.0);
    for (std::size_t i = 0; i < cell.size(); ++i) {
      const auto c = static_cast<std::size_t>(cell[i]);
      sum[c] += samples.area[i] * samples.points[i];
      area[c] += samples.area[i];
    }
    // The projections in parallel (each centre on its own), then the empty cells' centres dropped.
    std::vector<Vec3> projected(centres.size());
    tbb::parallel_for(std::size_t{0}, centres.size(), [&](std::size_t c) {
      if (area[c] <= 0.0) return;
      const Vec3 target = centres[c] + kOverRelaxation * (sum[c] / area[c] - centres[c]);
      projected[c] = surface.closest_point(target).value_or(target);
    });
    std::vector<Vec3> moved;
    moved.reserve(centres.size());
    for (std::size_t c = 0; c < centres.size(); ++c)
      if (area[c] > 0.0) moved.push_back(projected[c]);
    if (moved.size() != centres.size()) cell.clear();  // the indices moved: no hints next time
    centres = std::move(moved);
  }
  return centres;
}

namespace {

// The spreading after Lloyd's iteration (docs/solver.md "Layout"): kSpreadIterations steps, each moving
// a centre kSpreadStep times the sum of how much closer than the mean the nearer of its kSpreadNeighbours
// nearest are (a Jacobi step on springs that only push). A prototype on the sphere (6 mm at 10 mm, seeds
// 1-5, the layout's own centres, Lloyd's NN CV 0.048): 0.25 brings the NN CV to 0.034 after 15 steps,
// 0.030 after 30, 0.027 after 60; 0.5 overshoots and oscillates (0.057); 0.1 gives 0.035 after 30 (the
// written meshes' figures: at kSettleIterations).
constexpr int kSpreadIterations = 60;
constexpr double kSpreadStep = 0.25;
constexpr std::size_t kSpreadNeighbours = 6;

// No centre moves further than this (times the spacing) from where Lloyd's iteration put it: the
// spreading mends Lloyd's layout locally. On the bunny (8 mm at 14 mm) without the settling below, 179
// of 189 preview holes stayed within 0.15 spacing of the full run's unbounded, 183 with 0.2 (Lloyd's
// layout: 182); with the settling 182 either way. On the sphere it costs 0.0013 of cell-area CV and
// 0.0004 of NN CV.
constexpr double kMaxShift = 0.2;

// Over-relaxed Lloyd iterations after the spreading. The equation takes about twice the steps from the
// spread layout as from Lloyd's; a couple of Lloyd iterations bring the cells' centroids back to the
// centres and the steps back down, keeping most of the gain. Sphere, 6 mm at 10 mm, written meshes
// (cell-area CV, NN CV, paper-rule steps): Lloyd alone 0.059, 0.048, 17-21; spread 30 steps, no
// settling 0.050, 0.035, 32-44; 30 and 2 iterations 0.049, 0.038, 17-22; 60 and 2 iterations 0.046,
// 0.036, 17-23 (seeds 1-5). Seeds 1-3: 60 and none 0.047, 0.033, 38-39; 30 and 1 iteration 21-23 steps;
// 30 and 3: 0.049, 0.039, 17-19.
constexpr int kSettleIterations = 2;

// A centre moves only with the whole disc of one spacing a around it free: at least this share of pi a^2
// of free area within a of it (a plane's share and a sphere's is 1, curvature adds a little; a centre
// 0.84 a from a straight edge of the free area has 0.95). The others, along solid zones and open edges,
// stay where Lloyd's iteration put them: pushed from inside, they would have only the zone to go to.
constexpr double kFreeDisc = 0.95;

// The free area within r of each point: the samples in cubes of side r, each point's 27 cubes searched
// in a fixed order.
std::vector<double> area_within(const AreaSamples& samples, std::span<const Vec3> points, double r) {
  using Key = std::array<std::int64_t, 3>;
  const auto key_of = [r](const Vec3& p) {
    return Key{static_cast<std::int64_t>(std::floor(p.x() / r)),
               static_cast<std::int64_t>(std::floor(p.y() / r)),
               static_cast<std::int64_t>(std::floor(p.z() / r))};
  };
  std::vector<std::pair<Key, std::size_t>> sorted(samples.points.size());
  for (std::size_t i = 0; i < sorted.size(); ++i) sorted[i] = {key_of(samples.points[i]), i};
  std::sort(sorted.begin(), sorted.end());
  std::vector<double> area(points.size(), 0.0);
  tbb::parallel_for(std::size_t{0}, points.size(), [&](std::size_t q) {
    const Key at = key_of(points[q]);
    for (std::int64_t dx = -1; dx <= 1; ++dx)
      for (std::int64_t dy = -1; dy <= 1; ++dy)
        for (std::int64_t dz = -1; dz <= 1; ++dz) {
          const Key k{at[0] + dx, at[1] + dy, at[2] + dz};
          auto it = std::lower_bound(sorted.begin(), sorted.end(), std::pair{k, std::size_t{0}});
          for (; it != sorted.end() && it->first == k; ++it)
            if ((samples.points[it->second] - points[q]).squaredNorm() <= r * r)
              area[q] += samples.area[it->second];
        }
  });
  return area;
}

}  // namespace

std::vector<Vec3> spread_centres(std::vector<Vec3> centres, const AreaSamples& samples,
                                 const Surface& surface, double spacing, double reach, int iterations) {
  const std::size_t n = centres.size();
  if (n <= kSpreadNeighbours || samples.points.empty()) return centres;
  const std::vector<double> around = area_within(samples, centres, spacing);
  std::vector<std::size_t> moving;
  for (std::size_t c = 0; c < n; ++c)
    if (around[c] >= kFreeDisc * std::numbers::pi * spacing * spacing) moving.push_back(c);
  if (moving.empty()) return centres;
  const PointTree free(samples.points);
  const std::size_t k = kSpreadNeighbours;
  std::vector<std::size_t> near(moving.size() * k);
  std::vector<double> dist(moving.size() * k);
  const std::vector<Vec3> start = centres;
  for (int it = 0; it < iterations; ++it) {
    const PointTree tree(centres);
    tbb::parallel_for(std::size_t{0}, moving.size(), [&](std::size_t m) {
      const std::size_t c = moving[m];
      std::size_t j = m * k;
      for (const std::size_t other : tree.k_nearest(centres[c], k + 1))
        if (other != c && j < (m + 1) * k) {
          near[j] = other;
          dist[j++] = (centres[other] - centres[c]).norm();
        }
    });
    // In order: the same mean on any thread count.
    const double mean = std::accumulate(dist.begin(), dist.end(), 0.0) / static_cast<double>(dist.size());
    std::vector<Vec3> target(moving.size());
    tbb::parallel_for(std::size_t{0}, moving.size(), [&](std::size_t m) {
      const Vec3& x = centres[moving[m]];
      Vec3 push = Vec3::Zero();
      for (std::size_t j = m * k; j < (m + 1) * k; ++j)
        if (dist[j] < mean && dist[j] > 0.0) push += (mean - dist[j]) / dist[j] * (x - centres[near[j]]);
      target[m] = x + kSpreadStep * push;
    });
    // A move further than kMaxShift from the start, or out of the free area (no sample within `reach`
    // of the moved centre, nor as near as to the centre before), is not taken.
    // Each centre on its own: parallel, the same on any thread count.
    std::vector<Vec3> next = centres;
    tbb::parallel_for(std::size_t{0}, moving.size(), [&](std::size_t m) {
      const std::size_t c = moving[m];
      const Vec3 moved = surface.closest_point(target[m]).value_or(target[m]);
      if ((moved - start[c]).norm() > kMaxShift * spacing) return;
      if (free.nearest(moved).second <= std::max(reach, free.nearest(centres[c]).second)) next[c] = moved;
    });
    centres = std::move(next);
  }
  return centres;
}

std::vector<AreaSamples> free_parts(const NarrowBand& band, const AreaSamples& samples) {
  std::vector<std::int32_t> sample_of(band.size(), -1);
  for (std::size_t i = 0; i < samples.voxel.size(); ++i)
    sample_of[static_cast<std::size_t>(samples.voxel[i])] = static_cast<std::int32_t>(i);
  // Each sample joined to its +x, +y and +z neighbours (6-adjacency: the layer |psi| < h, 2 h thick, is
  // 6-connected wherever the surface is).
  DisjointSets sets(samples.voxel.size());
  for (std::size_t i = 0; i < samples.voxel.size(); ++i)
    for (const int n : {1, 3, 5}) {
      const std::int32_t w = band.neighbor(static_cast<std::size_t>(samples.voxel[i]), n);
      if (w < 0 || static_cast<std::size_t>(w) >= band.size()) continue;  // off the layer, or a ghost
      if (const std::int32_t j = sample_of[static_cast<std::size_t>(w)]; j >= 0)
        sets.unite(static_cast<std::int32_t>(i), j);
    }
  std::vector<std::int32_t> part_of_root(samples.voxel.size(), -1);
  std::vector<AreaSamples> parts;
  for (std::size_t i = 0; i < samples.voxel.size(); ++i) {
    std::int32_t& part = part_of_root[static_cast<std::size_t>(sets.find(static_cast<std::int32_t>(i)))];
    if (part < 0) {
      part = static_cast<std::int32_t>(parts.size());
      parts.emplace_back();
    }
    AreaSamples& p = parts[static_cast<std::size_t>(part)];
    p.points.push_back(samples.points[i]);
    p.area.push_back(samples.area[i]);
    p.voxel.push_back(samples.voxel[i]);
  }
  return parts;
}

std::vector<Vec3> farthest_point_centres(const AreaSamples& samples, std::size_t count, std::uint64_t seed) {
  std::vector<Vec3> centres;
  const std::size_t n = samples.points.size();
  if (n == 0 || count == 0) return centres;
  const double total = std::accumulate(samples.area.begin(), samples.area.end(), 0.0);
  // splitmix64 of the seed: a fraction of the area, the same on every platform.
  std::uint64_t z = seed + 0x9E3779B97F4A7C15ULL;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  z ^= z >> 31;
  const double target = total * static_cast<double>(z >> 11) * 0x1.0p-53;
  std::size_t first = 0;
  for (double sum = 0.0; first + 1 < n && (sum += samples.area[first]) < target;) ++first;
  // The samples in cubes about a hole's spacing wide, each with its box and its farthest sample from the
  // centres so far (the lowest index among equals, as a scan of all would pick). A new centre updates
  // only the cubes whose box comes nearer to it than their farthest sample: after the first few centres
  // a handful each, where every sample was updated before (the bunny at 3 mm holes, 2,000 centres over
  // 500k samples: a fifth of a single-threaded preview). The same centres as the scan of all samples.
  const double side = std::sqrt(total / static_cast<double>(count));
  using Key = std::array<std::int64_t, 3>;
  std::vector<std::pair<Key, std::size_t>> sorted(n);
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3& p = samples.points[i];
    sorted[i] = {Key{static_cast<std::int64_t>(std::floor(p.x() / side)),
                     static_cast<std::int64_t>(std::floor(p.y() / side)),
                     static_cast<std::int64_t>(std::floor(p.z() / side))},
                 i};
  }
  std::sort(sorted.begin(), sorted.end());
  struct Cube {
    std::size_t begin = 0, end = 0;  // into `sorted`
    Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity());
    Vec3 hi = -Vec3::Constant(std::numeric_limits<double>::infinity());
    double farthest = std::numeric_limits<double>::infinity();  // squared distance
    std::size_t at = 0;  // its sample (the lowest index among equals); set by the first centre's update
  };
  std::vector<Cube> cubes;
  for (std::size_t i = 0; i < n; ++i) {
    if (i == 0 || sorted[i].first != sorted[i - 1].first) cubes.push_back({i, i});
    Cube& cube = cubes.back();
    cube.end = i + 1;
    cube.lo = cube.lo.cwiseMin(samples.points[sorted[i].second]);
    cube.hi = cube.hi.cwiseMax(samples.points[sorted[i].second]);
  }
  std::vector<double> dist2(n, std::numeric_limits<double>::infinity());
  std::size_t next = first;
  while (centres.size() < std::min(count, n)) {
    const Vec3 c = samples.points[next];
    centres.push_back(c);
    tbb::parallel_for(std::size_t{0}, cubes.size(), [&](std::size_t q) {
      Cube& cube = cubes[q];
      const double gap2 = (cube.lo - c).cwiseMax(c - cube.hi).cwiseMax(0.0).squaredNorm();
      if (gap2 > cube.farthest * (1.0 + 1e-9)) return;  // no sample of it comes nearer (rounding slack)
      cube.farthest = -1.0;
      for (std::size_t j = cube.begin; j < cube.end; ++j) {
        const std::size_t i = sorted[j].second;
        dist2[i] = std::min(dist2[i], (samples.points[i] - c).squaredNorm());
        if (dist2[i] > cube.farthest || (dist2[i] == cube.farthest && i < cube.at)) {
          cube.farthest = dist2[i];
          cube.at = i;
        }
      }
    });
    const Cube* best = &cubes.front();
    for (const Cube& cube : cubes)
      if (cube.farthest > best->farthest || (cube.farthest == best->farthest && cube.at < best->at))
        best = &cube;
    next = best->at;
  }
  return centres;
}

std::vector<Vec3> clear_of_open_edges(std::vector<Vec3> centres, std::span<const Segment> open_edges,
                                      double clearance) {
  if (open_edges.empty() || centres.empty() || !(clearance > 0.0)) return centres;
  const std::vector<double> distance = segment_distances(centres, open_edges, clearance);
  std::size_t kept = 0;
  for (std::size_t c = 0; c < centres.size(); ++c)
    if (distance[c] >= clearance) centres[kept++] = centres[c];
  centres.resize(kept);
  return centres;
}

std::vector<double> disc_field(const NarrowBand& band, std::span<const Vec3> centres, double radius,
                               double epsilon, std::span<const double> zone_weight,
                               std::optional<double> mean) {
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
  if (!mean) return phi;
  // Sequential sums: the same bytes on any thread count.
  double sum = 0.0, free_sum = 0.0;
  for (std::size_t v = 0; v < phi.size(); ++v) {
    sum += phi[v];
    free_sum += free(v);
  }
  if (free_sum <= 0.0) return phi;
  const double shift = (*mean * static_cast<double>(phi.size()) - sum) / free_sum;
  for (std::size_t v = 0; v < phi.size(); ++v) phi[v] += shift * free(v);
  return phi;
}

std::vector<Vec3> merge_overlapping_centres(std::vector<Vec3> centres, double diameter,
                                            const Surface& surface) {
  for (;;) {
    if (centres.size() < 2) return centres;
    const PointTree tree(centres);
    std::size_t a = 0, b = 0;
    double closest = diameter;
    for (std::size_t i = 0; i < centres.size(); ++i) {
      const std::size_t j = tree.k_nearest(centres[i], 2)[1];
      if (const double d = (centres[j] - centres[i]).norm(); d < closest) {
        closest = d;
        a = std::min(i, j);
        b = std::max(i, j);
      }
    }
    if (a == b) return centres;
    const Vec3 middle = 0.5 * (centres[a] + centres[b]);
    centres[a] = surface.closest_point(middle).value_or(middle);
    centres.erase(centres.begin() + static_cast<std::ptrdiff_t>(b));
  }
}

std::vector<Vec3> even_layout(const NarrowBand& band, const Surface& surface,
                              std::span<const double> zone_weight, double spacing, std::uint64_t seed) {
  const AreaSamples samples = area_samples(band, zone_weight, kZoneMargin * spacing);
  std::vector<Vec3> centres;
  for (const AreaSamples& part : free_parts(band, samples)) {
    const double area = std::accumulate(part.area.begin(), part.area.end(), 0.0);
    const auto count = static_cast<std::size_t>(std::lround(area / (kAreaPerHole * spacing * spacing)));
    for (const Vec3& c : farthest_point_centres(part, count, seed)) centres.push_back(c);
  }
  centres = lloyd_centres(std::move(centres), samples, surface, kLloydIterations);
  centres = spread_centres(std::move(centres), samples, surface, spacing, band.grid().h(), kSpreadIterations);
  return lloyd_centres(std::move(centres), samples, surface, kSettleIterations);
}

}  // namespace poreshell
