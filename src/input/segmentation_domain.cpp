#include "input/segmentation_domain.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <unordered_set>

namespace poreshell {

SegmentationDomain find_segmentation_domain(const Grid& lattice, const PointTree& tree, double width) {
  std::unordered_set<std::int64_t> seen;
  std::vector<std::int64_t> frontier;
  for (std::size_t i = 0; i < tree.size(); ++i) {
    const Vec3 q = lattice.to_index_space(tree.point(i));
    const Coord c{static_cast<int>(std::lround(q.x())), static_cast<int>(std::lround(q.y())),
                  static_cast<int>(std::lround(q.z()))};
    if (seen.insert(lattice.key(c)).second) frontier.push_back(lattice.key(c));
  }
  std::sort(frontier.begin(), frontier.end());
  SegmentationDomain d;
  std::vector<std::pair<std::int64_t, double>> band;
  while (!frontier.empty()) {
    std::vector<double> g(frontier.size());
    tbb::parallel_for(std::size_t{0}, frontier.size(), [&](std::size_t f) {
      g[f] = tree.nearest(lattice.position(lattice.coord(frontier[f]))).second;
    });
    std::vector<std::int64_t> next;
    for (std::size_t f = 0; f < frontier.size(); ++f) {
      if (!(g[f] < width)) {
        d.ghost.push_back(frontier[f]);
        continue;
      }
      band.emplace_back(frontier[f], g[f]);
      const Coord c = lattice.coord(frontier[f]);
      for (const Coord& o : kFaceOffsets) {
        const Coord nb = shifted(c, o);
        if (!lattice.contains(nb))
          throw std::logic_error("segmentation: the lattice is too small for its band");
        if (seen.insert(lattice.key(nb)).second) next.push_back(lattice.key(nb));
      }
    }
    std::sort(next.begin(), next.end());
    frontier = std::move(next);
  }
  std::sort(band.begin(), band.end());
  std::sort(d.ghost.begin(), d.ghost.end());
  for (const auto& [key, g] : band) {
    d.band.push_back(key);
    d.band_g.push_back(g);
  }
  return d;
}

std::vector<signed char> label_sides(const Grid& lattice, const SegmentationDomain& d, double blocked,
                                     std::int64_t& inside_band) {
  const std::size_t n = d.band.size(), m = d.ghost.size();
  std::vector<signed char> side(n + m, 0);  // 0: not yet known
  const auto index = [&](const Coord& c) -> std::int64_t {
    if (!lattice.contains(c)) return -1;
    const std::int64_t key = lattice.key(c);
    if (const auto b = find_key(d.band, key); b >= 0) return b;
    if (const auto g = find_key(d.ghost, key); g >= 0) return static_cast<std::int64_t>(n) + g;
    return -1;
  };
  const auto coord_of = [&](std::size_t v) { return lattice.coord(v < n ? d.band[v] : d.ghost[v - n]); };
  const auto open = [&](std::size_t v) { return v >= n || !(d.band_g[v] < blocked); };

  // Flood the outside from the ghost with the lowest key (the bottom of the domain: outside).
  std::vector<std::size_t> stack{n};
  side[n] = 1;
  while (!stack.empty()) {
    const std::size_t v = stack.back();
    stack.pop_back();
    const Coord c = coord_of(v);
    for (int dk = -1; dk <= 1; ++dk)
      for (int dj = -1; dj <= 1; ++dj)
        for (int di = -1; di <= 1; ++di) {
          const int manhattan = std::abs(di) + std::abs(dj) + std::abs(dk);
          if (manhattan == 0) continue;
          const std::int64_t w = index({c.i + di, c.j + dj, c.k + dk});
          if (w < 0 || side[static_cast<std::size_t>(w)] != 0 || !open(static_cast<std::size_t>(w))) continue;
          // Diagonal steps only from ghost to ghost.
          if (manhattan > 1 && (v < n || static_cast<std::size_t>(w) < n)) continue;
          side[static_cast<std::size_t>(w)] = 1;
          stack.push_back(static_cast<std::size_t>(w));
        }
  }
  inside_band = 0;
  for (std::size_t v = 0; v < n + m; ++v)
    if (side[v] == 0 && open(v)) {
      side[v] = -1;
      inside_band += v < n;
    }

  // Blocked voxels: breadth-first from the labelled ones, a layer at a time; the side is the sign of
  // the sum of the labelled neighbours' sides (ties: outside).
  std::vector<std::size_t> pending;
  for (std::size_t v = 0; v < n; ++v)
    if (side[v] == 0) pending.push_back(v);
  while (!pending.empty()) {
    std::vector<std::pair<std::size_t, signed char>> decided;
    std::vector<std::size_t> still;
    for (const std::size_t v : pending) {
      int sum = 0, known = 0;
      for (const Coord& o : kFaceOffsets) {
        const std::int64_t w = index(shifted(coord_of(v), o));
        if (w >= 0 && side[static_cast<std::size_t>(w)] != 0) {
          sum += side[static_cast<std::size_t>(w)];
          ++known;
        }
      }
      if (known > 0)
        decided.emplace_back(v, static_cast<signed char>(sum < 0 ? -1 : 1));
      else
        still.push_back(v);
    }
    if (decided.empty()) {  // an isolated pocket of blocked voxels: call it outside
      for (const std::size_t v : still) side[v] = 1;
      break;
    }
    for (const auto& [v, s] : decided) side[v] = s;
    pending = std::move(still);
  }
  return side;
}

}  // namespace poreshell
