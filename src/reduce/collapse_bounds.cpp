#include "reduce/collapse_bounds.hpp"

#include <tbb/parallel_for.h>

#include <Eigen/Geometry>  // cross()

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <limits>
#include <stdexcept>
#include <utility>

namespace poreshell {
namespace {

constexpr int kMaxWalk = 16;  // steps across the original surface before a best-first search
// Triangles a best-first search looks at, at most: about a tolerance-wide patch of the original
// around the point is a few tens.
constexpr std::size_t kMaxVisits = 1024;

}  // namespace

std::vector<std::int32_t> opposite_corners(const TriangleMesh& mesh, const VertexTriangles& at) {
  std::vector<std::int32_t> opposite(3 * mesh.triangles.size(), -1);
  // Corner c faces the edge u -> w of its triangle; the corner across faces w -> u, in the triangle
  // at w where w is followed by u. Both lie in w's fan: one pass per vertex pairs the corners whose
  // edge ends there, reading each triangle of the fan once, where a pass per corner read the whole
  // fan for each (bunny's 1.5 M-triangle shell: 0.13 s -> 0.06 s, the same table).
  tbb::parallel_for(std::size_t{0}, mesh.vertices.size(), [&](std::size_t x) {
    const auto w = static_cast<std::int32_t>(x);
    struct Side {
      std::int32_t next, previous;  // the vertices after and before w in the triangle
      std::int32_t triangle;
      int k;  // w's position in it
    };
    std::array<Side, 32> local;
    std::vector<Side> spill;
    const std::uint32_t count = at.start[x + 1] - at.start[x];
    Side* fan = local.data();
    if (count > local.size()) {
      spill.resize(count);
      fan = spill.data();
    }
    for (std::uint32_t j = 0; j < count; ++j) {
      const auto f = static_cast<std::int32_t>(at.incident[at.start[x] + j]);
      const auto& t = mesh.triangles[static_cast<std::size_t>(f)];
      const int k = place_of(t, w);
      fan[j] = {t[static_cast<std::size_t>((k + 1) % 3)], t[static_cast<std::size_t>((k + 2) % 3)], f, k};
    }
    // The corner after w faces previous -> w; across it, the first triangle of the fan in which w is
    // followed by that vertex.
    for (std::uint32_t j = 0; j < count; ++j)
      for (std::uint32_t i = 0; i < count; ++i)
        if (fan[i].next == fan[j].previous) {
          opposite[static_cast<std::size_t>(3 * fan[j].triangle + (fan[j].k + 1) % 3)] =
              3 * fan[i].triangle + (fan[i].k + 2) % 3;
          break;
        }
  });
  if (std::find(opposite.begin(), opposite.end(), -1) != opposite.end())
    throw std::runtime_error("mesh decimation: an edge has no triangle across it");
  return opposite;
}

OriginalSurface::OriginalSurface(const TriangleMesh& mesh, const std::vector<std::int32_t>& opposite,
                                 VertexTriangles around)
    : mesh_(mesh), opposite_(opposite), around_(std::move(around)) {
  bounds_.resize(mesh.triangles.size());
  tbb::parallel_for(std::size_t{0}, bounds_.size(), [&](std::size_t f) {
    const auto& t = mesh.triangles[f];
    const Vec3 &a = mesh.vertices[t[0]], &b = mesh.vertices[t[1]], &c = mesh.vertices[t[2]];
    const Vec3 center = (a + b + c) / 3.0;
    const double radius = std::max({(a - center).norm(), (b - center).norm(), (c - center).norm()});
    bounds_[f] = {center, radius, classify_triangle(a, b, c)};
  });
  // Each corner weighted by its angle, so that the slivers of an isosurface mesh count for little.
  // Summed per vertex over its triangles in ascending order: the same sums on any thread count.
  normals_.assign(mesh.vertices.size(), Vec3::Zero());
  tbb::parallel_for(std::size_t{0}, normals_.size(), [&](std::size_t v) {
    Vec3 sum = Vec3::Zero();
    for (const std::uint32_t f : triangles_at(static_cast<std::int32_t>(v))) {
      const auto& t = mesh.triangles[f];
      const int i = place_of(t, static_cast<std::int32_t>(v));
      const Vec3 &p = mesh.vertices[t[i]], &q = mesh.vertices[t[(i + 1) % 3]],
                 &r = mesh.vertices[t[(i + 2) % 3]];
      // The angle from the cross product's length and the dot product, no edge normalised: on the
      // bunny's 1.5 M-triangle shell 0.11-0.14 s against 0.16-0.21 s with the arc cosine of unit edges.
      const Vec3 cross = (q - p).cross(r - p);
      const double sine = cross.norm();
      if (sine > 0.0) sum += (std::atan2(sine, (q - p).dot(r - p)) / sine) * cross;
    }
    normals_[v] = sum.stableNormalized();
  });
}

double OriginalSurface::gap(const Vec3& p, std::int32_t f) const {
  const Bound& b = bounds_[static_cast<std::size_t>(f)];
  return std::max((p - b.center).norm() - b.radius, 0.0);
}

double OriginalSurface::distance2(const Vec3& p, std::int32_t f) const {
  const auto& t = mesh_.triangles[static_cast<std::size_t>(f)];
  const Vec3 q = closest_point_on_triangle(p, mesh_.vertices[t[0]], mesh_.vertices[t[1]],
                                           mesh_.vertices[t[2]], bounds_[static_cast<std::size_t>(f)].shape);
  return (q - p).squaredNorm();
}

bool OriginalSurface::near(const Vec3& p, std::initializer_list<std::int32_t> anchors,
                           double tolerance) const {
  const double tolerance2 = tolerance * tolerance;
  return distance2_from(p, anchors, tolerance2) <= tolerance2;
}

double OriginalSurface::distance2_from(const Vec3& p, std::initializer_list<std::int32_t> anchors,
                                       double enough2) const {
  // First a walk from where a bounding sphere comes nearest, across edges while that comes closer. The
  // anchors' triangles' gaps are kept for the second look at them (as many as fit).
  std::array<double, 48> gaps;
  std::size_t count = 0;
  std::int32_t at = -1;
  double least_gap = std::numeric_limits<double>::infinity();
  for (const std::int32_t v : anchors)
    for (const std::uint32_t f : triangles_at(v)) {
      const double g = gap(p, static_cast<std::int32_t>(f));
      if (count < gaps.size()) gaps[count] = g;
      ++count;
      if (g < least_gap) {
        least_gap = g;
        at = static_cast<std::int32_t>(f);
      }
    }
  const std::int32_t first = at;
  double best = distance2(p, at);
  auto visit = [&](std::int32_t f, double g) {
    if (g * g >= best) return;
    if (const double d2 = distance2(p, f); d2 < best) {
      best = d2;
      at = f;
    }
  };
  std::size_t i = 0;
  for (const std::int32_t v : anchors)
    for (const std::uint32_t f : triangles_at(v)) {
      if (best <= enough2) return best;
      const auto t = static_cast<std::int32_t>(f);
      // `first`'s distance is best or more: asking again cannot lower it.
      if (t != first) visit(t, i < gaps.size() ? gaps[i] : gap(p, t));
      ++i;
    }
  // The triangle a step came from is no nearer than where it went: not asked again.
  for (std::int32_t step = 0, behind = -1; step < kMaxWalk && best > enough2; ++step) {
    const std::int32_t from = at;
    for (int k = 0; k < 3; ++k)
      if (const std::int32_t f = opposite_[static_cast<std::size_t>(3 * from + k)] / 3; f != behind)
        visit(f, gap(p, f));
    if (at == from) break;
    behind = from;
  }
  if (best <= enough2) return best;
  // Stuck short of `enough2`: best-first from there and from the anchors. (squared gap, triangle),
  // nearest on top; the triangles seen, sorted: a few tens as a rule.
  std::vector<std::pair<double, std::int32_t>> open;
  std::vector<std::int32_t> seen;
  const auto offer = [&](std::int32_t f) {
    const auto place = std::lower_bound(seen.begin(), seen.end(), f);
    if (place != seen.end() && *place == f) return;
    seen.insert(place, f);
    const double g = gap(p, f);
    if (g * g > best) return;  // `at` gets in: its gap is at most its distance, which is best
    open.emplace_back(g * g, f);
    std::push_heap(open.begin(), open.end(), std::greater<>());
  };
  offer(at);
  for (const std::int32_t v : anchors)
    for (const std::uint32_t f : triangles_at(v)) offer(static_cast<std::int32_t>(f));
  while (!open.empty() && seen.size() <= kMaxVisits) {
    std::pop_heap(open.begin(), open.end(), std::greater<>());
    const auto [gap2, f] = open.back();
    open.pop_back();
    if (gap2 > best) break;  // the rest are further still
    best = std::min(best, distance2(p, f));
    if (best <= enough2) break;
    for (int k = 0; k < 3; ++k) offer(opposite_[static_cast<std::size_t>(3 * f + k)] / 3);
  }
  return best;
}

}  // namespace poreshell
