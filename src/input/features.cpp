#include "input/features.hpp"

#include <tbb/parallel_for.h>

#include <Eigen/Geometry>  // cross()
#include <algorithm>
#include <cmath>
#include <numbers>
#include <numeric>
#include <queue>
#include <tuple>

#include "core/disjoint_sets.hpp"
#include "geometry/point_tree.hpp"

namespace poreshell {
namespace {

using Edge = std::pair<std::int32_t, std::int32_t>;

// Neighbours that pass on a point cloud's orientation: a few more than a splat's plane fit takes.
constexpr std::size_t kOrientingNeighbours = 12;
constexpr double kLeastDepthInSpacings = 2.0;

Vec3 face_normal(const TriangleMesh& m, const std::array<std::int32_t, 3>& t) {
  const Vec3& a = m.vertices[static_cast<std::size_t>(t[0])];
  return (m.vertices[static_cast<std::size_t>(t[1])] - a)
      .cross(m.vertices[static_cast<std::size_t>(t[2])] - a);
}

// Whether the ball of radius t touching the surface at p from the side `in` (unit) leaves the surface
// closer than 0.9 t for t at 1/4, 1/2, 3/4 and 1 of `radius` (those at least `least_t`): a part
// thinner than 2 radius there.
bool thin_along(const Surface& surface, const Vec3& p, const Vec3& in, double radius, double least_t = 0.0) {
  // The deepest point first: the distance is 1-Lipschitz, so d(p_s) >= d(p_1) - (1 - s) radius, and
  // where that clears 0.9 s radius for every s (d(p_1) >= 0.98 radius: most of a surface that is not
  // thin), the other three queries cannot find the part thin. Same answer, a third of the queries.
  const double deepest = surface.distance(p + radius * in);
  if (deepest < 0.9 * radius) return true;
  if (deepest >= 0.98 * radius) return false;
  for (double share : {0.25, 0.5, 0.75}) {
    const double t = share * radius;
    if (t >= least_t && surface.distance(p + t * in) < 0.9 * t) return true;
  }
  return false;
}

// The marks grown by `margin`: points within it of a thin one, where a hole centred would reach into the
// thin part.
std::vector<double> grow_marks(std::span<const Vec3> points, const std::vector<double>& thin, double margin) {
  if (margin <= 0.0) return thin;
  std::vector<Vec3> marked;
  for (std::size_t v = 0; v < thin.size(); ++v)
    if (thin[v] > 0.0) marked.push_back(points[v]);
  if (marked.empty()) return thin;
  const PointTree tree(marked);
  std::vector<double> grown(thin.size(), 0.0);
  tbb::parallel_for(std::size_t{0}, points.size(),
                    [&](std::size_t v) { grown[v] = tree.nearest(points[v]).second <= margin ? 1.0 : 0.0; });
  return grown;
}

// Thin where no ball of radius R fits nearby. Each point's ball touches it from inside (along `inward`,
// unit, or zero where it has none): where it fits, its centre is a centre of a ball of the hole's scale
// inside the part. A point is thin where no fitting centre lies within R + margin of it: a scan's grooves
// and bumps tilt a point's own normal, or leave its ball short of room, though its neighbours' balls fit
// beside it (issue 51: the armadillo's relief read as thin, 74% of its vertices against 33-38% by the
// ball test at the hole's scale); a thin part has no fitting ball anywhere near. `least_t`: per point,
// the smallest depth tested (0 for every depth).
std::vector<double> thin_by_balls(std::span<const Vec3> points, std::span<const Vec3> inward,
                                  std::span<const double> least_t, const Surface& surface, double radius,
                                  double margin) {
  std::vector<char> fits(points.size(), 0);
  std::vector<Vec3> centre(points.size(), Vec3::Zero());
  tbb::parallel_for(std::size_t{0}, points.size(), [&](std::size_t v) {
    if (inward[v].squaredNorm() == 0.0) return;
    centre[v] = points[v] + radius * inward[v];
    fits[v] = thin_along(surface, points[v], inward[v], radius, least_t.empty() ? 0.0 : least_t[v]) ? 0 : 1;
  });
  std::vector<Vec3> fitted;
  for (std::size_t v = 0; v < fits.size(); ++v)
    if (fits[v]) fitted.push_back(centre[v]);
  std::vector<double> thin(points.size(), 1.0);
  if (!fitted.empty()) {
    const PointTree tree(fitted);
    const double reach = radius + margin;
    tbb::parallel_for(std::size_t{0}, points.size(), [&](std::size_t v) {
      thin[v] = fits[v] || tree.nearest(points[v]).second <= reach ? 0.0 : 1.0;
    });
  }
  return grow_marks(points, thin, margin);
}

std::vector<double> thin_vertices(const TriangleMesh& mesh, const Surface& surface, const FeatureOptions& o) {
  std::vector<Vec3> normal(mesh.vertices.size(), Vec3::Zero());
  double volume = 0.0;
  for (const auto& t : mesh.triangles) {
    const Vec3 n = face_normal(mesh, t);  // area-weighted
    for (std::int32_t v : t) normal[static_cast<std::size_t>(v)] += n;
    volume += mesh.vertices[static_cast<std::size_t>(t[0])].dot(n) / 6.0;
  }
  const double inward = volume >= 0.0 ? -1.0 : 1.0;
  for (Vec3& n : normal)
    if (n.squaredNorm() > 0.0) n = inward * n.normalized();
  return thin_by_balls(mesh.vertices, normal, {}, surface, 0.5 * o.thin_below, o.margin);
}

// Sharp edges (dihedral above the angle, both faces present), kept where they chain through shared
// vertices into a crease at least min_crease_length long.
std::vector<std::array<Vec3, 2>> crease_segments(const TriangleMesh& mesh, const FeatureOptions& o) {
  // (edge, face) for every side of every triangle, sorted: an edge's faces are then adjacent, first two
  // in face order (a sorted array, not a map: a fifth of the time on the bunny).
  std::vector<std::pair<Edge, std::int32_t>> sides;
  sides.reserve(3 * mesh.triangles.size());
  for (std::size_t f = 0; f < mesh.triangles.size(); ++f)
    for (int k = 0; k < 3; ++k) {
      const std::int32_t a = mesh.triangles[f][static_cast<std::size_t>(k)],
                         b = mesh.triangles[f][static_cast<std::size_t>((k + 1) % 3)];
      sides.push_back({{std::min(a, b), std::max(a, b)}, static_cast<std::int32_t>(f)});
    }
  std::sort(sides.begin(), sides.end());
  const double cos_limit = std::cos(o.crease_degrees * std::numbers::pi / 180.0);
  std::vector<Edge> sharp;
  for (std::size_t i = 0; i < sides.size();) {
    std::size_t end = i + 1;
    while (end < sides.size() && sides[end].first == sides[i].first) ++end;
    if (end - i >= 2) {  // one face: a boundary edge, the rim's business
      const Vec3 n0 =
          face_normal(mesh, mesh.triangles[static_cast<std::size_t>(sides[i].second)]).normalized();
      const Vec3 n1 =
          face_normal(mesh, mesh.triangles[static_cast<std::size_t>(sides[i + 1].second)]).normalized();
      if (n0.allFinite() && n1.allFinite() && n0.dot(n1) < cos_limit) sharp.push_back(sides[i].first);
    }
    i = end;
  }
  // Chains: union-find over the sharp edges' vertices, length per chain.
  DisjointSets chains(mesh.vertices.size());
  for (const Edge& e : sharp) chains.unite(e.first, e.second);
  std::vector<double> length(mesh.vertices.size(), 0.0);
  const auto segment = [&](const Edge& e) {
    return std::array<Vec3, 2>{mesh.vertices[static_cast<std::size_t>(e.first)],
                               mesh.vertices[static_cast<std::size_t>(e.second)]};
  };
  for (const Edge& e : sharp) {
    const auto s = segment(e);
    length[static_cast<std::size_t>(chains.find(e.first))] += (s[1] - s[0]).norm();
  }
  std::vector<std::array<Vec3, 2>> creases;
  for (const Edge& e : sharp)
    if (length[static_cast<std::size_t>(chains.find(e.first))] >= o.min_crease_length)
      creases.push_back(segment(e));
  return creases;
}

}  // namespace

std::vector<Vec3> oriented_normals(std::span<const Vec3> points, std::span<const Vec3> normals,
                                   const PointTree& tree) {
  // The neighbour graph, both ways: a point another one counts among its nearest is its neighbour too.
  // As one array (`first` indexes each point's run), not a vector per point: 8 bytes an edge.
  const std::size_t n = points.size(), k = std::min(kOrientingNeighbours, n);
  std::vector<std::uint32_t> nearest(n * k);
  tbb::parallel_for(std::size_t{0}, n, [&](std::size_t v) {
    const std::vector<std::size_t> near = tree.k_nearest(points[v], k);
    for (std::size_t i = 0; i < k; ++i) nearest[v * k + i] = static_cast<std::uint32_t>(near[i]);
  });
  std::vector<std::size_t> first(n + 1, 0);
  for (std::size_t v = 0; v < n; ++v)
    for (std::size_t i = 0; i < k; ++i) {
      ++first[v + 1];
      ++first[nearest[v * k + i] + 1];
    }
  for (std::size_t v = 0; v < n; ++v) first[v + 1] += first[v];
  std::vector<std::uint32_t> neighbours(first[n]);
  std::vector<std::size_t> fill(first.begin(), first.end() - 1);
  for (std::size_t v = 0; v < n; ++v)
    for (std::size_t i = 0; i < k; ++i) {
      const std::uint32_t u = nearest[v * k + i];
      neighbours[fill[v]++] = u;
      neighbours[fill[u]++] = static_cast<std::uint32_t>(v);
    }
  // Prim's tree of least bend, each point turned to agree with the one it is reached from; each part of
  // the graph starts at its point of largest x, whose outward normal has a positive x.
  std::vector<Vec3> out(normals.begin(), normals.end());
  std::vector<char> done(n, 0);
  std::vector<std::size_t> by_x(n);
  std::iota(by_x.begin(), by_x.end(), std::size_t{0});
  std::sort(by_x.begin(), by_x.end(), [&](std::size_t a, std::size_t b) {
    return points[a].x() != points[b].x() ? points[a].x() > points[b].x() : a < b;
  });
  // How little the side passes on from v to u: normals apart, or u off v's tangent plane (across a sheet
  // thinner than the neighbours' reach, where the normals are parallel but the sides opposite).
  const auto bend = [&](std::size_t u, std::size_t v) {
    const Vec3 along = (points[u] - points[v]).stableNormalized();  // zero for a repeated point
    return 1.0 - std::abs(out[u].dot(out[v])) +
           0.5 * (std::abs(out[u].dot(along)) + std::abs(out[v].dot(along)));
  };
  using Step = std::tuple<double, std::size_t, std::size_t>;  // (bend, point, the point it is reached from)
  std::priority_queue<Step, std::vector<Step>, std::greater<>> queue;
  for (const std::size_t seed : by_x) {
    if (done[seed]) continue;
    if (out[seed].x() < 0.0) out[seed] = -out[seed];
    queue.emplace(0.0, seed, seed);
    while (!queue.empty()) {
      const auto [cost, v, from] = queue.top();
      queue.pop();
      if (done[v]) continue;
      done[v] = 1;
      if (out[v].dot(out[from]) < 0.0) out[v] = -out[v];
      for (std::size_t i = first[v]; i < first[v + 1]; ++i)
        if (const std::size_t u = neighbours[i]; !done[u]) queue.emplace(bend(u, v), u, v);
    }
  }
  return out;
}

std::vector<double> thin_points(std::span<const Vec3> points, std::span<const Vec3> normals,
                                std::span<const double> spacing, const PointTree& tree,
                                const Surface& surface, const FeatureOptions& options) {
  if (!(options.thin_below > 0.0)) return std::vector<double>(points.size(), 0.0);
  std::vector<Vec3> inward = oriented_normals(points, normals, tree);
  for (Vec3& n : inward) n = -n;
  // Within a few spacings of the point its neighbours' splats, tilted by their normals' noise, come
  // closer than 0.9 t (a third of the bunny's points looked thin): depths from twice the spacing on.
  std::vector<double> least_t(spacing.begin(), spacing.end());
  for (double& t : least_t) t *= kLeastDepthInSpacings;
  return thin_by_balls(points, inward, least_t, surface, 0.5 * options.thin_below, options.margin);
}

SurfaceFeatures find_surface_features(const TriangleMesh& mesh, const Surface& surface,
                                      const FeatureOptions& options) {
  SurfaceFeatures f;
  if (options.thin_below > 0.0) {
    f.thin = thin_vertices(mesh, surface, options);
    f.thin_vertices = static_cast<std::int64_t>(std::count(f.thin.begin(), f.thin.end(), 1.0));
  }
  if (options.crease_degrees > 0.0) {
    f.creases = crease_segments(mesh, options);
    f.crease_edges = static_cast<std::int64_t>(f.creases.size());
  }
  return f;
}

}  // namespace poreshell
