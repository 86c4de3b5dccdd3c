#include "input/point_segmentation.hpp"

#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <numeric>
#include <stdexcept>
#include <string>
#include <unordered_set>

#include "core/error.hpp"
#include "geometry/isosurface.hpp"
#include "geometry/mesh_surface.hpp"

namespace poreshell {
namespace {

constexpr std::array<Coord, 6> kFaces{{{-1, 0, 0}, {1, 0, 0}, {0, -1, 0}, {0, 1, 0}, {0, 0, -1}, {0, 0, 1}}};

Coord add(const Coord& a, const Coord& b) {
  return {a.i + b.i, a.j + b.j, a.k + b.k};
}

bool lexicographic_less(const Vec3& a, const Vec3& b) {
  return std::lexicographical_compare(a.data(), a.data() + 3, b.data(), b.data() + 3);
}

double double_well(double psi) {  // F(psi) = (psi^2 - 1)^2 / 4
  const double s = psi * psi - 1.0;
  return 0.25 * s * s;
}

// The sparse domain of eq. (3.3): lattice voxels with g < width, found by a breadth-first search from
// the voxels nearest the points (never a dense array), and its ghost layer: their 6-neighbours with
// g >= width. Both sorted by key, with g at each.
struct Domain {
  std::vector<std::int64_t> band, ghost;
  std::vector<double> band_g;
};

Domain find_domain(const Grid& lattice, const PointTree& tree, double width) {
  std::unordered_set<std::int64_t> seen;
  std::vector<std::int64_t> frontier;
  for (std::size_t i = 0; i < tree.size(); ++i) {
    const Vec3 q = lattice.to_index_space(tree.point(i));
    const Coord c{static_cast<int>(std::lround(q.x())), static_cast<int>(std::lround(q.y())),
                  static_cast<int>(std::lround(q.z()))};
    if (seen.insert(lattice.key(c)).second) frontier.push_back(lattice.key(c));
  }
  std::sort(frontier.begin(), frontier.end());
  Domain d;
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
      for (const Coord& o : kFaces) {
        const Coord nb = add(c, o);
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

std::int64_t find_key(const std::vector<std::int64_t>& keys, std::int64_t key) {
  const auto it = std::lower_bound(keys.begin(), keys.end(), key);
  return (it != keys.end() && *it == key) ? it - keys.begin() : -1;
}

// Inside (-1) or outside (+1) for every band and ghost voxel. Outside is what a flood from the lowest
// ghost voxel reaches: through ghosts (26-neighbours: the ghost layer is only 26-connected in places;
// it lies a whole band width from the points, so a diagonal step cannot cross the surface) and through
// band voxels farther than `blocked` from the points (6-neighbours: a 6-path that crosses the surface
// passes a voxel within h/2 of it, which is within `blocked` of a point). Band voxels nearer the points
// take the side of their nearest labelled neighbours.
std::vector<signed char> label_sides(const Grid& lattice, const Domain& d, double blocked,
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
      for (const Coord& o : kFaces) {
        const std::int64_t w = index(add(coord_of(v), o));
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

}  // namespace

std::vector<Vec3> densify_patches(const std::vector<Vec3>& points, const Triangles& triangles,
                                  double tolerance, std::size_t max_points) {
  if (!(tolerance > 0.0)) throw InputError("the densification tolerance must be positive");
  std::vector<Vec3> out = points;
  struct Tri {
    Vec3 a, b, c;
  };
  std::vector<Tri> stack;
  for (const auto& t : triangles) {
    for (const std::int32_t v : t)
      if (v < 0 || static_cast<std::size_t>(v) >= points.size())
        throw InputError("a patch refers to a point that does not exist");
    stack.push_back({points[static_cast<std::size_t>(t[0])], points[static_cast<std::size_t>(t[1])],
                     points[static_cast<std::size_t>(t[2])]});
    while (!stack.empty()) {
      const Tri tri = stack.back();
      stack.pop_back();
      const double ab = (tri.b - tri.a).norm(), bc = (tri.c - tri.b).norm(), ca = (tri.a - tri.c).norm();
      if (std::max({ab, bc, ca}) < tolerance) continue;
      if (out.size() >= max_points)
        throw InputError("densifying the patches would make more than " + std::to_string(max_points) +
                         " points: use a coarser grid");
      // Split the longest edge at its midpoint; (p + q) / 2 is symmetric in p and q, so the triangle on
      // the other side of the edge produces the very same point.
      if (ab >= bc && ab >= ca) {
        const Vec3 m = 0.5 * (tri.a + tri.b);
        out.push_back(m);
        stack.push_back({tri.a, m, tri.c});
        stack.push_back({m, tri.b, tri.c});
      } else if (bc >= ca) {
        const Vec3 m = 0.5 * (tri.b + tri.c);
        out.push_back(m);
        stack.push_back({tri.a, tri.b, m});
        stack.push_back({tri.a, m, tri.c});
      } else {
        const Vec3 m = 0.5 * (tri.c + tri.a);
        out.push_back(m);
        stack.push_back({tri.a, tri.b, m});
        stack.push_back({m, tri.b, tri.c});
      }
    }
  }
  std::sort(out.begin() + static_cast<std::ptrdiff_t>(points.size()), out.end(), lexicographic_less);
  out.erase(std::unique(out.begin() + static_cast<std::ptrdiff_t>(points.size()), out.end()), out.end());
  return out;
}

Triangles umbrella_patches(const std::vector<Vec3>& points, std::vector<char>* boundary, int neighbors) {
  if (boundary) boundary->assign(points.size(), 0);
  if (points.size() < 4) return {};
  const PointTree tree(points);
  std::vector<Triangles> per_point(points.size());
  tbb::parallel_for(std::size_t{0}, points.size(), [&](std::size_t i) {
    const auto near = tree.k_nearest(points[i], static_cast<std::size_t>(neighbors) + 1);
    Vec3 mean = Vec3::Zero();
    for (const std::size_t j : near) mean += points[j];
    mean /= static_cast<double>(near.size());
    Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
    for (const std::size_t j : near) cov += (points[j] - mean) * (points[j] - mean).transpose();
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov);
    const Vec3 u = eig.eigenvectors().col(2), v = eig.eigenvectors().col(1);
    std::vector<std::pair<double, std::size_t>> ring;
    for (const std::size_t j : near) {
      const Vec3 d = points[j] - points[i];
      if (j == i || d.squaredNorm() == 0.0) continue;
      ring.emplace_back(std::atan2(d.dot(v), d.dot(u)), j);
    }
    std::sort(ring.begin(), ring.end());
    for (std::size_t r = 0; r < ring.size() && ring.size() >= 2; ++r) {
      const auto& [a0, j0] = ring[r];
      const auto& [a1, j1] = ring[(r + 1) % ring.size()];
      const double gap = r + 1 < ring.size() ? a1 - a0 : a1 + 2.0 * std::numbers::pi - a0;
      if (gap >= 2.0 * std::numbers::pi / 3.0) {  // a border, or a hole
        if (boundary) (*boundary)[i] = 1;
        continue;
      }
      std::array<std::int32_t, 3> t{static_cast<std::int32_t>(i), static_cast<std::int32_t>(j0),
                                    static_cast<std::int32_t>(j1)};
      std::sort(t.begin(), t.end());
      per_point[i].push_back(t);
    }
  });
  Triangles out;
  for (const auto& p : per_point) out.insert(out.end(), p.begin(), p.end());
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

std::vector<char> boundary_vertices(std::size_t points, const Triangles& triangles) {
  std::vector<std::pair<std::int32_t, std::int32_t>> edges;
  for (const auto& t : triangles)
    for (int k = 0; k < 3; ++k)
      edges.emplace_back(std::minmax(t[static_cast<std::size_t>(k)], t[(k + 1) % 3]));
  std::sort(edges.begin(), edges.end());
  std::vector<char> boundary(points, 0);
  for (std::size_t e = 0; e < edges.size();) {
    std::size_t f = e;
    while (f < edges.size() && edges[f] == edges[e]) ++f;
    if (f - e == 1)
      boundary[static_cast<std::size_t>(edges[e].first)] =
          boundary[static_cast<std::size_t>(edges[e].second)] = 1;
    e = f;
  }
  return boundary;
}

int cap_holes(std::vector<Vec3>& points, Triangles& triangles, const std::vector<char>& boundary,
              std::size_t min_points) {
  std::vector<std::size_t> rim;
  for (std::size_t i = 0; i < boundary.size(); ++i)
    if (boundary[i]) rim.push_back(i);
  if (rim.size() < min_points) return 0;
  // Link rim points closer than five sample spacings (the median nearest-neighbour distance): with
  // three, the bunny's rims split into pieces at N = 131 and their caps leave gaps.
  const PointTree all(points);
  std::vector<double> spacing(points.size());
  tbb::parallel_for(std::size_t{0}, points.size(), [&](std::size_t i) {
    const auto near = all.k_nearest(points[i], 2);
    spacing[i] = near.size() > 1 ? (points[near[1]] - points[i]).norm() : 0.0;
  });
  std::nth_element(spacing.begin(), spacing.begin() + static_cast<std::ptrdiff_t>(spacing.size() / 2),
                   spacing.end());
  const double link = 5.0 * spacing[spacing.size() / 2];
  std::vector<Vec3> rim_points;
  for (const std::size_t i : rim) rim_points.push_back(points[i]);
  const PointTree rim_tree(rim_points);
  std::vector<std::size_t> parent(rim.size());
  std::iota(parent.begin(), parent.end(), 0);
  const auto root = [&](std::size_t a) {
    while (parent[a] != a) a = parent[a] = parent[parent[a]];
    return a;
  };
  for (std::size_t a = 0; a < rim.size(); ++a)
    for (const std::size_t b : rim_tree.k_nearest(rim_points[a], 12))
      if ((rim_points[b] - rim_points[a]).norm() < link) {
        const std::size_t ra = root(a), rb = root(b);
        parent[std::max(ra, rb)] = std::min(ra, rb);  // the smaller root wins: deterministic
      }
  std::vector<std::vector<std::size_t>> loops(rim.size());
  for (std::size_t a = 0; a < rim.size(); ++a) loops[root(a)].push_back(a);
  int caps = 0;
  for (const auto& loop : loops) {
    if (loop.size() < min_points) continue;
    // A fan from the rim's centroid over the rim points ordered by angle in the rim's best-fit plane.
    Vec3 c = Vec3::Zero();
    for (const std::size_t a : loop) c += rim_points[a];
    c /= static_cast<double>(loop.size());
    Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
    for (const std::size_t a : loop) cov += (rim_points[a] - c) * (rim_points[a] - c).transpose();
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov);
    const Vec3 u = eig.eigenvectors().col(2), v = eig.eigenvectors().col(1);
    std::vector<std::pair<double, std::size_t>> ring;
    for (const std::size_t a : loop)
      ring.emplace_back(std::atan2((rim_points[a] - c).dot(v), (rim_points[a] - c).dot(u)), rim[a]);
    std::sort(ring.begin(), ring.end());
    const auto center = static_cast<std::int32_t>(points.size());
    points.push_back(c);
    for (std::size_t r = 0; r < ring.size(); ++r)
      triangles.push_back({center, static_cast<std::int32_t>(ring[r].second),
                           static_cast<std::int32_t>(ring[(r + 1) % ring.size()].second)});
    ++caps;
  }
  return caps;
}

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
        const double w = (di ? t.x() : 1 - t.x()) * (dj ? t.y() : 1 - t.y()) * (dk ? t.z() : 1 - t.z());
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

std::unique_ptr<SampledLevelSet> segment_point_cloud(const std::vector<Vec3>& input_points,
                                                     const Triangles& input_triangles, const Grid& grid,
                                                     const SegmentationOptions& o, SegmentationStats* stats) {
  const double h = grid.h();
  if (!(o.band_in_h >= 3.0)) throw InputError("the segmentation band must be at least 3 h wide");
  if (!(o.epsilon_in_h > 0.0) || o.max_iterations < 0 || !(o.tolerance > 0.0))
    throw InputError("segmentation: epsilon, iterations and tolerance must be positive");
  SegmentationStats st;

  // (a) Fig. 8: densify the patches (the input's own, or each point's umbrella).
  const double tol = o.densify_tolerance_in_h * h;
  std::vector<Vec3> patch_points = input_points;
  std::vector<char> boundary;
  Triangles patches = input_triangles.empty() ? umbrella_patches(input_points, &boundary) : input_triangles;
  if (!input_triangles.empty()) boundary = boundary_vertices(input_points.size(), input_triangles);
  // Scans have holes (the bunny's base); the segmentation needs a closed surface, so cap them first.
  st.hole_caps = o.cap_holes ? cap_holes(patch_points, patches, boundary, 6) : 0;
  const std::vector<Vec3> points = densify_patches(patch_points, patches, tol);
  st.points = static_cast<std::int64_t>(points.size());
  const PointTree tree(points);

  // The sampling lattice: the grid's own points (an integer offset from its origin), wide enough for
  // the band, its ghost layer and the trilinear cells around them.
  Box box{points.front(), points.front()};
  for (const Vec3& p : points) {
    box.min = box.min.cwiseMin(p);
    box.max = box.max.cwiseMax(p);
  }
  const double width = o.band_in_h * h;
  const int margin = static_cast<int>(std::ceil(o.band_in_h)) + 3;
  std::array<int, 3> lo{}, dims{};
  for (int a = 0; a < 3; ++a) {
    lo[static_cast<std::size_t>(a)] =
        static_cast<int>(std::floor((box.min[a] - grid.origin()[a]) / h)) - margin;
    const int hi = static_cast<int>(std::ceil((box.max[a] - grid.origin()[a]) / h)) + margin;
    dims[static_cast<std::size_t>(a)] = hi - lo[static_cast<std::size_t>(a)] + 1;
  }
  const Grid lattice(grid.origin() + h * Vec3(lo[0], lo[1], lo[2]), h, dims);

  // (b) eq. (3.3) on the sparse band {g < width}, Dirichlet psi = +-1 on its ghost layer.
  const Domain d = find_domain(lattice, tree, width);
  const std::size_t n = d.band.size(), m = d.ghost.size();
  st.band_voxels = static_cast<std::int64_t>(n);
  st.ghost_voxels = static_cast<std::int64_t>(m);
  const std::vector<signed char> side = label_sides(lattice, d, 0.5 * h + tol, st.inside_voxels);
  std::int64_t inside_ghosts = 0;
  for (std::size_t g = 0; g < m; ++g) inside_ghosts += side[n + g] < 0;
  if (stats) *stats = st;
  if (st.inside_voxels == 0 && inside_ghosts == 0)
    throw InputError(
        "the paper's point-cloud route found no inside: the points do not enclose a volume at this "
        "resolution "
        "(a hole wider than about one voxel, or an open surface); use `point_route` direct, which needs no "
        "inside, or close the holes");

  const double eps = o.epsilon_in_h * h, eps2 = eps * eps;
  const double lambda = o.lambda_eps2 / eps2;
  std::vector<std::int32_t> neighbors(n * 6);
  tbb::parallel_for(std::size_t{0}, n, [&](std::size_t v) {
    const Coord c = lattice.coord(d.band[v]);
    for (std::size_t f = 0; f < 6; ++f) {
      const std::int64_t key = lattice.key(add(c, kFaces[f]));
      std::int64_t idx = find_key(d.band, key);
      if (idx < 0) idx = static_cast<std::int64_t>(n) + find_key(d.ghost, key);  // always one or the other
      neighbors[v * 6 + f] = static_cast<std::int32_t>(idx);
    }
  });
  std::vector<double> psi(n + m), next(n + m);
  double g_max = 0.0;
  for (std::size_t v = 0; v < n + m; ++v) {
    const double g = v < n ? d.band_g[v] : width;
    g_max = std::max(g_max, g);
    psi[v] = v < n ? side[v] * std::tanh(g / (std::sqrt(2.0) * eps)) : side[v];
  }
  next = psi;
  // Explicit Euler; stable for dt g (12/h^2 + 2/eps^2) < 2 (the Laplacian's and the double well's
  // largest rates); half of that.
  const double dt = 1.0 / (g_max * (12.0 / (h * h) + 2.0 / eps2));
  int it = 0;
  double change = 0.0;
  for (it = 1; it <= o.max_iterations; ++it) {
    change = tbb::parallel_reduce(
        tbb::blocked_range<std::size_t>(0, n), 0.0,
        [&](const tbb::blocked_range<std::size_t>& r, double worst) {
          for (std::size_t v = r.begin(); v < r.end(); ++v) {
            const double p = psi[v];
            double lap = -6.0 * p;
            for (std::size_t f = 0; f < 6; ++f) lap += psi[static_cast<std::size_t>(neighbors[v * 6 + f])];
            lap /= h * h;
            const double rate = -(p * p * p - p) / eps2 + lap + lambda * double_well(p);
            next[v] = p + dt * d.band_g[v] * rate;
            worst = std::max(worst, std::abs(next[v] - p));
          }
          return worst;
        },
        [](double a, double b) { return std::max(a, b); });
    std::swap(psi, next);
    if (change < o.tolerance) break;
  }
  st.iterations = std::min(it, o.max_iterations);
  st.last_change = change;
  st.dt = dt;
  st.epsilon = eps;
  st.lambda = lambda;

  // The zero level of psi (marching cubes over band and ghosts). The solid's far side, where the inner
  // ghost layer (-1) meets the background (+1), is a second, spurious sheet a band width from the points;
  // keep only the sheet near the points.
  std::vector<Coord> coords(n + m);
  for (std::size_t v = 0; v < n + m; ++v) coords[v] = lattice.coord(v < n ? d.band[v] : d.ghost[v - n]);
  TriangleMesh level = extract_isosurface(SparseField{&lattice, coords, psi, 1.0}, 0.0);
  TriangleMesh kept;
  kept.vertices = level.vertices;
  for (const auto& t : level.triangles) {
    const Vec3 centroid =
        (level.vertices[static_cast<std::size_t>(t[0])] + level.vertices[static_cast<std::size_t>(t[1])] +
         level.vertices[static_cast<std::size_t>(t[2])]) /
        3.0;
    if (tree.nearest(centroid).second < 0.5 * width) kept.triangles.push_back(t);
  }
  if (stats) *stats = st;
  if (kept.triangles.empty())
    throw InputError(
        "the paper's point-cloud route found no surface in the segmentation; use `point_route` direct");
  st.zero_level_triangles = static_cast<std::int64_t>(kept.triangles.size());
  for (const auto& t : kept.triangles)
    for (const std::int32_t v : t)
      st.zero_level_max_gap =
          std::max(st.zero_level_max_gap, tree.nearest(kept.vertices[static_cast<std::size_t>(v)]).second);

  // The discrete signed distance: the sign of psi, the exact distance to its zero level.
  const MeshSurface zero_level(kept);
  std::vector<std::pair<std::int64_t, double>> samples(n + m);
  tbb::parallel_for(std::size_t{0}, n + m, [&](std::size_t v) {
    const double dist = zero_level.distance(lattice.position(coords[v]));
    samples[v] = {lattice.key(coords[v]), psi[v] < 0.0 ? -dist : dist};
  });
  std::sort(samples.begin(), samples.end());
  std::vector<std::int64_t> keys(samples.size());
  std::vector<double> values(samples.size());
  for (std::size_t v = 0; v < samples.size(); ++v) std::tie(keys[v], values[v]) = samples[v];
  if (stats) *stats = st;
  // The zero level's triangles reach at most half an edge (< h) beyond their vertices.
  return std::make_unique<SampledLevelSet>(lattice, std::move(keys), std::move(values), points,
                                           st.zero_level_max_gap + h, &kept);
}

}  // namespace poreshell
