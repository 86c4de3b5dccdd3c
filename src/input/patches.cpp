#include "input/patches.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <numeric>
#include <string>

#include "core/error.hpp"
#include "geometry/mesh.hpp"
#include "geometry/plane_fit.hpp"
#include "geometry/point_tree.hpp"

namespace poreshell {
namespace {

bool lexicographic_less(const Vec3& a, const Vec3& b) {
  return std::lexicographical_compare(a.data(), a.data() + 3, b.data(), b.data() + 3);
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
    const PlaneFit plane = fit_plane(points, near);
    const Vec3 u = plane.major(), v = plane.minor();
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
  std::vector<char> boundary(points, 0);
  for (const Edge& e : boundary_edges(points, triangles))
    boundary[static_cast<std::size_t>(e[0])] = boundary[static_cast<std::size_t>(e[1])] = 1;
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
    const PlaneFit plane = fit_plane(rim_points, loop);
    const Vec3 c = plane.centroid, u = plane.major(), v = plane.minor();
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

}  // namespace poreshell
