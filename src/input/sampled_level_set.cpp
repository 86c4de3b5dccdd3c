#include "input/sampled_level_set.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "core/trilinear.hpp"

namespace poreshell {

SampledLevelSet::SampledLevelSet(const Grid& lattice, std::vector<std::int64_t> keys,
                                 std::vector<double> values, std::vector<Vec3> points, double gap,
                                 const TriangleMesh* zero_level)
    : lattice_(lattice),
      keys_(std::move(keys)),
      values_(std::move(values)),
      points_(std::move(points)),
      tree_(points_),
      gap_(gap),
      zero_level_(zero_level ? std::make_unique<MeshSurface>(*zero_level) : nullptr) {
  if (keys_.size() != values_.size() || !std::is_sorted(keys_.begin(), keys_.end()))
    throw std::invalid_argument("SampledLevelSet: keys must be ascending, one value each");
}

std::optional<double> SampledLevelSet::sample(const Coord& c) const {
  if (!lattice_.contains(c)) return std::nullopt;
  const std::int64_t i = find_key(keys_, lattice_.key(c));
  if (i < 0) return std::nullopt;
  return values_[static_cast<std::size_t>(i)];
}

double SampledLevelSet::distance(const Vec3& p) const {
  const Vec3 q = lattice_.to_index_space(p);
  // Lattice points (all the band builder asks at on the pipeline's grid) need one sample, not eight:
  // snap coordinates that are integers up to round-off.
  Coord base;
  Vec3 t;
  std::array<int, 3> span{};
  for (int a = 0; a < 3; ++a) {
    const double r = std::round(q[a]);
    const bool on_lattice = std::abs(q[a] - r) < 1e-9;
    const double f = on_lattice ? r : std::floor(q[a]);
    (a == 0 ? base.i : a == 1 ? base.j : base.k) = static_cast<int>(f);
    t[a] = on_lattice ? 0.0 : q[a] - f;
    span[static_cast<std::size_t>(a)] = on_lattice ? 1 : 2;
  }
  double value = 0.0, nearest_weight = -1.0;
  int nearest_sign = 1;
  bool complete = true;
  for (int dk = 0; dk < span[2]; ++dk)
    for (int dj = 0; dj < span[1]; ++dj)
      for (int di = 0; di < span[0]; ++di) {
        const double w = trilinear_weight(t, di + 2 * dj + 4 * dk);
        const std::optional<double> s = sample({base.i + di, base.j + dj, base.k + dk});
        if (!s) {
          complete = false;
          continue;
        }
        value += w * *s;
        if (w > nearest_weight) {
          nearest_weight = w;
          nearest_sign = *s < 0.0 ? -1 : 1;
        }
      }
  if (complete && (span == std::array<int, 3>{1, 1, 1} || !zero_level_)) return value;
  // Off the lattice (block centres, the fast solver's coarse grids) or beyond the samples: the unsigned
  // distance to the zero level, as the mesh route gives. Signed values there made the coarse bands
  // lose the mid-surface of thin parts (|grad psi| -> 0 at the kink).
  if (zero_level_) return zero_level_->distance(p);
  // Else a lower bound of |distance| (g is 1-Lipschitz and the zero level lies within gap_ of the
  // points), signed like the nearest sample.
  return nearest_sign * std::max(0.0, tree_.nearest(p).second - gap_);
}

std::optional<Vec3> SampledLevelSet::closest_point(const Vec3& p) const {
  if (!zero_level_) return std::nullopt;
  // Off the lattice (the multigrid's coarse grids, not the paper's grid): the exact closest point.
  const Vec3 q = lattice_.to_index_space(p);
  for (int a = 0; a < 3; ++a)
    if (std::abs(q[a] - std::round(q[a])) > 1e-9) return zero_level_->closest_point(p);
  const double h = lattice_.h();
  Vec3 g;
  for (int a = 0; a < 3; ++a) {
    Vec3 e = Vec3::Zero();
    e[a] = h;
    g[a] = (distance(p + e) - distance(p - e)) / (2.0 * h);
  }
  if (std::abs(g.norm() - 1.0) <= 0.1) return std::nullopt;
  return zero_level_->closest_point(p);
}

Box SampledLevelSet::bounds() const {
  Box box{points_.front(), points_.front()};
  for (const Vec3& p : points_) {
    box.min = box.min.cwiseMin(p);
    box.max = box.max.cwiseMax(p);
  }
  // The zero level reaches at most gap_ past the points. The margin (not a whole number of cells) also
  // keeps the fast solver's coarse grids, which start a whole number of their cells before this box,
  // off the lattice: there the band gets the unsigned distance and exact closest points, as for a mesh.
  box.min -= Vec3::Constant(gap_);
  box.max += Vec3::Constant(gap_);
  return box;
}

}  // namespace poreshell
