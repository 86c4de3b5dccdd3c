#include "poreshell/mesh.hpp"

// Topology checks by sorting instead of hashing: an edge table of 3F (edge, triangle) records
// sorted once, and a vertex -> triangle table built by counting sort. Both scale to millions of
// triangles without per-edge allocations.

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>
#include <tbb/parallel_sort.h>

#include <Eigen/Geometry>  // cross()
#include <algorithm>
#include <cmath>
#include <numbers>
#include <numeric>
#include <utility>

namespace poreshell {
namespace {

// Union-find with path halving; small and allocation-free after construction.
class DisjointSets {
 public:
  explicit DisjointSets(std::size_t n) : parent_(n) { std::iota(parent_.begin(), parent_.end(), 0); }
  std::size_t find(std::size_t x) {
    while (parent_[x] != x) x = parent_[x] = parent_[parent_[x]];
    return x;
  }
  void unite(std::size_t a, std::size_t b) {
    a = find(a);
    b = find(b);
    if (a != b) parent_[std::max(a, b)] = std::min(a, b);
  }

 private:
  std::vector<std::size_t> parent_;
};

struct EdgeRecord {
  std::uint64_t key;  // (min vertex << 32) | max vertex
  std::int64_t tri;   // triangle index
  bool forward;       // traversed from min to max
};

std::uint64_t edge_key(std::int32_t a, std::int32_t b) {
  const auto lo = static_cast<std::uint32_t>(std::min(a, b));
  const auto hi = static_cast<std::uint32_t>(std::max(a, b));
  return (std::uint64_t{lo} << 32) | hi;
}

bool has_repeated_index(const std::array<std::int32_t, 3>& t) {
  return t[0] == t[1] || t[1] == t[2] || t[0] == t[2];
}

bool zero_area(const TriangleMesh& mesh, const std::array<std::int32_t, 3>& t) {
  const Vec3& a = mesh.vertices[t[0]];
  const Vec3& b = mesh.vertices[t[1]];
  const Vec3& c = mesh.vertices[t[2]];
  const double longest2 = std::max({(b - a).squaredNorm(), (c - b).squaredNorm(), (a - c).squaredNorm()});
  // Relative to the longest edge so the test does not depend on the model's units; the factor
  // is a few ulps, i.e. "collinear up to round-off".
  return (b - a).cross(c - a).norm() <= 1e-14 * longest2;
}

// Counts vertices whose incident triangles do not form one edge-connected fan. Triangles around
// v are linked when they share an edge (v, x), i.e. both contain the same other vertex x.
std::int64_t count_nonmanifold_vertices(const TriangleMesh& mesh, const std::vector<char>& used) {
  const std::size_t nv = mesh.vertices.size();
  std::vector<std::int64_t> start(nv + 1, 0);
  for (const auto& t : mesh.triangles)
    if (!has_repeated_index(t))
      for (std::int32_t v : t) ++start[v + 1];
  std::partial_sum(start.begin(), start.end(), start.begin());
  std::vector<std::int64_t> incident(static_cast<std::size_t>(start[nv]));
  {
    std::vector<std::int64_t> fill(start.begin(), start.end() - 1);
    for (std::size_t f = 0; f < mesh.triangles.size(); ++f) {
      const auto& t = mesh.triangles[f];
      if (has_repeated_index(t)) continue;
      for (std::int32_t v : t) incident[fill[v]++] = static_cast<std::int64_t>(f);
    }
  }
  return tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(0, nv), std::int64_t{0},
      [&](const tbb::blocked_range<std::size_t>& r, std::int64_t count) {
        std::vector<std::pair<std::int32_t, std::size_t>> others;  // (other vertex, local triangle)
        for (std::size_t v = r.begin(); v != r.end(); ++v) {
          const std::size_t n = start[v + 1] - start[v];
          if (!used[v] || n <= 1) continue;
          others.clear();
          for (std::size_t i = 0; i < n; ++i) {
            const auto& t = mesh.triangles[incident[start[v] + i]];
            for (std::int32_t x : t)
              if (x != static_cast<std::int32_t>(v)) others.emplace_back(x, i);
          }
          std::sort(others.begin(), others.end());
          DisjointSets sets(n);
          for (std::size_t i = 1; i < others.size(); ++i)
            if (others[i].first == others[i - 1].first) sets.unite(others[i].second, others[i - 1].second);
          for (std::size_t i = 1; i < n; ++i)
            if (sets.find(i) != 0) {
              ++count;
              break;
            }
        }
        return count;
      },
      std::plus<>());
}

// Cosine of a triangle's smallest angle (1 for a zero-length side).
double largest_angle_cosine(const TriangleMesh& mesh, const std::array<std::int32_t, 3>& t) {
  double largest = -1.0;
  for (int c = 0; c < 3; ++c) {
    const Vec3& p = mesh.vertices[static_cast<std::size_t>(t[c])];
    const Vec3 u = mesh.vertices[static_cast<std::size_t>(t[(c + 1) % 3])] - p;
    const Vec3 w = mesh.vertices[static_cast<std::size_t>(t[(c + 2) % 3])] - p;
    const double norms = u.norm() * w.norm();
    largest = std::max(largest, norms > 0.0 ? u.dot(w) / norms : 1.0);
  }
  return largest;
}

}  // namespace

MeshTopology analyze_topology(const TriangleMesh& mesh) {
  MeshTopology topo;
  const std::size_t nf = mesh.triangles.size();
  const std::size_t nv = mesh.vertices.size();
  topo.triangles = static_cast<std::int64_t>(nf);

  std::vector<char> used(nv, 0);
  double min_cos = -1.0;  // cosine of the smallest angle seen
  std::vector<EdgeRecord> edges;
  edges.reserve(3 * nf);
  for (std::size_t f = 0; f < nf; ++f) {
    const auto& t = mesh.triangles[f];
    for (std::int32_t v : t) used.at(static_cast<std::size_t>(v)) = 1;  // at(): bad indices throw
    if (has_repeated_index(t)) {
      ++topo.degenerate_triangles;
      continue;  // its "edges" (a, a) are not edges
    }
    if (zero_area(mesh, t)) ++topo.degenerate_triangles;
    min_cos = std::max(min_cos, largest_angle_cosine(mesh, t));
    for (int c = 0; c < 3; ++c) {
      const std::int32_t a = t[c], b = t[(c + 1) % 3];
      edges.push_back({edge_key(a, b), static_cast<std::int64_t>(f), a < b});
    }
  }
  topo.vertices = std::count(used.begin(), used.end(), char{1});
  topo.min_angle_degrees = nf ? std::acos(std::clamp(min_cos, -1.0, 1.0)) * 180.0 / std::numbers::pi : 0.0;

  tbb::parallel_sort(edges.begin(), edges.end(), [](const EdgeRecord& x, const EdgeRecord& y) {
    return x.key != y.key ? x.key < y.key : x.tri < y.tri;
  });

  DisjointSets components(nf);
  for (std::size_t i = 0; i < edges.size();) {
    std::size_t j = i + 1;
    while (j < edges.size() && edges[j].key == edges[i].key) ++j;
    const std::size_t n = j - i;
    ++topo.edges;
    if (n == 1) ++topo.boundary_edges;
    if (n > 2) ++topo.nonmanifold_edges;
    if (n == 2 && edges[i].forward == edges[i + 1].forward) ++topo.misoriented_edges;
    for (std::size_t k = i + 1; k < j; ++k)
      components.unite(static_cast<std::size_t>(edges[i].tri), static_cast<std::size_t>(edges[k].tri));
    i = j;
  }
  for (std::size_t f = 0; f < nf; ++f)
    if (components.find(f) == f) ++topo.components;

  topo.nonmanifold_vertices = count_nonmanifold_vertices(mesh, used);
  topo.euler_characteristic = topo.vertices - topo.edges + topo.triangles;

  // Divergence theorem about a point of the mesh: fewer cancelling digits than about the origin.
  // Summed serially so the result does not depend on the thread count.
  if (nf > 0) {
    const Vec3 ref = mesh.vertices[mesh.triangles[0][0]];
    double six_volume = 0.0;
    for (const auto& t : mesh.triangles) {
      const Vec3 a = mesh.vertices[t[0]] - ref, b = mesh.vertices[t[1]] - ref, c = mesh.vertices[t[2]] - ref;
      six_volume += a.dot(b.cross(c));
    }
    topo.signed_volume = six_volume / 6.0;
  }
  return topo;
}

}  // namespace poreshell
