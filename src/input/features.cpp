#include "input/features.hpp"

#include <tbb/parallel_for.h>

#include <Eigen/Geometry>  // cross()
#include <algorithm>
#include <cmath>
#include <numbers>

#include "core/disjoint_sets.hpp"
#include "geometry/point_tree.hpp"

namespace poreshell {
namespace {

using Edge = std::pair<std::int32_t, std::int32_t>;

// Points whose marks decide whether a point cloud's thin mark stands (itself included).
constexpr std::size_t kAgreeingNeighbours = 12;
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

std::vector<double> thin_vertices(const TriangleMesh& mesh, const Surface& surface, const FeatureOptions& o) {
  std::vector<Vec3> normal(mesh.vertices.size(), Vec3::Zero());
  double volume = 0.0;
  for (const auto& t : mesh.triangles) {
    const Vec3 n = face_normal(mesh, t);  // area-weighted
    for (std::int32_t v : t) normal[static_cast<std::size_t>(v)] += n;
    volume += mesh.vertices[static_cast<std::size_t>(t[0])].dot(n) / 6.0;
  }
  const double inward = volume >= 0.0 ? -1.0 : 1.0;
  const double radius = 0.5 * o.thin_below;
  // Each vertex's ball, touching it from inside along its normal: where it fits, its centre is a centre
  // of a ball of the hole's scale inside the part.
  std::vector<char> fits(mesh.vertices.size(), 0);
  std::vector<Vec3> centre(mesh.vertices.size(), Vec3::Zero());
  tbb::parallel_for(std::size_t{0}, mesh.vertices.size(), [&](std::size_t v) {
    if (normal[v].squaredNorm() == 0.0) return;
    const Vec3 in = inward * normal[v].normalized();
    centre[v] = mesh.vertices[v] + radius * in;
    fits[v] = thin_along(surface, mesh.vertices[v], in, radius) ? 0 : 1;
  });
  // Thin where no such ball comes near: no fitting centre within the ball's radius and half a hole
  // (kept in `margin`) of the vertex. A scan's grooves and bumps tilt a vertex's own normal, or leave its
  // ball short of room, though its neighbours' balls fit beside it (issue 51: the armadillo's relief read
  // as thin, 74% of its vertices against 33-38% by the ball test at the hole's scale); a thin part has
  // no fitting ball anywhere near.
  std::vector<Vec3> fitted;
  for (std::size_t v = 0; v < fits.size(); ++v)
    if (fits[v]) fitted.push_back(centre[v]);
  std::vector<double> thin(mesh.vertices.size(), 1.0);
  if (!fitted.empty()) {
    const PointTree tree(fitted);
    const double reach = radius + o.margin;
    tbb::parallel_for(std::size_t{0}, mesh.vertices.size(), [&](std::size_t v) {
      thin[v] = fits[v] || tree.nearest(mesh.vertices[v]).second <= reach ? 0.0 : 1.0;
    });
  }
  return grow_marks(mesh.vertices, thin, o.margin);
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

std::vector<double> thin_points(std::span<const Vec3> points, std::span<const Vec3> normals,
                                std::span<const double> spacing, const PointTree& tree,
                                const Surface& surface, const FeatureOptions& options) {
  std::vector<double> thin(points.size(), 0.0);
  if (!(options.thin_below > 0.0)) return thin;
  const double radius = 0.5 * options.thin_below;
  tbb::parallel_for(std::size_t{0}, points.size(), [&](std::size_t v) {
    const Vec3& n = normals[v];
    // Within a few spacings of the point its neighbours' splats, tilted by their normals' noise, come
    // closer than 0.9 t (a third of the bunny's points looked thin): depths from twice the spacing on.
    const double least_t = kLeastDepthInSpacings * spacing[v];
    if (n.squaredNorm() > 0.0 && (thin_along(surface, points[v], n, radius, least_t) ||
                                  thin_along(surface, points[v], -n, radius, least_t)))
      thin[v] = 1.0;
  });
  // A scan's stray points carry splats off the surface that make the points near them look thin; a
  // thin part's points are thin together. Keep a mark only where most of its neighbours have one.
  std::vector<double> kept(points.size(), 0.0);
  tbb::parallel_for(std::size_t{0}, points.size(), [&](std::size_t v) {
    if (thin[v] == 0.0) return;
    const std::vector<std::size_t> near = tree.k_nearest(points[v], kAgreeingNeighbours);
    std::size_t agree = 0;
    for (const std::size_t u : near) agree += thin[u] > 0.0 ? 1 : 0;
    kept[v] = 2 * agree > near.size() ? 1.0 : 0.0;
  });
  return grow_marks(points, kept, options.margin);
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
