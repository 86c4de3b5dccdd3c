#include "poreshell/mesh.hpp"

// Topology checks by sorting instead of hashing: a table of (edge, triangle) records sorted in passes
// over vertex ranges, and a vertex -> triangle table built by counting sort. Both scale to tens of
// millions of triangles without per-edge allocations.

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>
#include <tbb/parallel_sort.h>

#include <Eigen/Geometry>  // cross()
#include <algorithm>
#include <cmath>
#include <numbers>
#include <numeric>
#include <stdexcept>
#include <utility>

namespace poreshell {
namespace {

// Union-find with path halving; small and allocation-free after construction. 32-bit: triangle and
// vertex indices are int32 in TriangleMesh.
class DisjointSets {
 public:
  explicit DisjointSets(std::size_t n) : parent_(n) { std::iota(parent_.begin(), parent_.end(), 0u); }
  std::size_t find(std::size_t x) {
    while (parent_[x] != x) x = parent_[x] = parent_[parent_[x]];
    return x;
  }
  void unite(std::size_t a, std::size_t b) {
    a = find(a);
    b = find(b);
    if (a != b) parent_[std::max(a, b)] = static_cast<std::uint32_t>(std::min(a, b));
  }

 private:
  std::vector<std::uint32_t> parent_;
};

// One triangle's side: the undirected edge and its direction in one sortable word, (min vertex << 32 |
// max vertex) << 1 | forward (indices are below 2^31), and the triangle. 16 bytes: at 24 M triangles the
// table is the largest array of the whole run, so it is also built in vertex ranges (below).
struct EdgeRecord {
  std::uint64_t key;
  std::uint32_t tri;
  std::uint64_t edge() const { return key >> 1; }
  bool forward() const { return key & 1; }
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
  std::vector<std::uint32_t> incident(static_cast<std::size_t>(start[nv]));
  // Filled with start[v] as v's cursor (it ends at v's end, the next vertex's start), then shifted
  // back: no second table of offsets.
  for (std::size_t f = 0; f < mesh.triangles.size(); ++f) {
    const auto& t = mesh.triangles[f];
    if (has_repeated_index(t)) continue;
    for (std::int32_t v : t) incident[static_cast<std::size_t>(start[v]++)] = static_cast<std::uint32_t>(f);
  }
  for (std::size_t v = nv; v > 0; --v) start[v] = start[v - 1];
  start[0] = 0;
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

MeshTopology analyze_topology(const TriangleMesh& mesh, std::size_t edge_table_bytes) {
  MeshTopology topo;
  const std::size_t nf = mesh.triangles.size();
  const std::size_t nv = mesh.vertices.size();
  topo.triangles = static_cast<std::int64_t>(nf);

  if (nf >= std::size_t{1} << 31) throw std::invalid_argument("analyze_topology: over 2^31 triangles");
  std::vector<char> used(nv, 0);
  double min_cos = -1.0;  // cosine of the smallest angle seen
  for (const auto& t : mesh.triangles) {
    for (std::int32_t v : t) used.at(static_cast<std::size_t>(v)) = 1;  // at(): bad indices throw
    if (has_repeated_index(t)) {
      ++topo.degenerate_triangles;
      continue;  // its "edges" (a, a) are not edges
    }
    if (zero_area(mesh, t)) ++topo.degenerate_triangles;
    min_cos = std::max(min_cos, largest_angle_cosine(mesh, t));
  }
  topo.vertices = std::count(used.begin(), used.end(), char{1});
  topo.min_angle_degrees = nf ? std::acos(std::clamp(min_cos, -1.0, 1.0)) * 180.0 / std::numbers::pi : 0.0;

  // Edges sorted in passes over ranges of their smaller vertex, so the table stays under
  // edge_table_bytes however large the mesh (an edge's records all fall in one pass).
  const std::size_t records = 3 * nf;
  const std::size_t passes =
      std::max<std::size_t>(1, records * sizeof(EdgeRecord) / std::max<std::size_t>(1, edge_table_bytes) + 1);
  const std::size_t per_pass = nv / passes + 1;
  {  // the sets are freed before the vertex pass below
    DisjointSets components(nf);
    std::vector<EdgeRecord> edges;
    edges.reserve(std::min(records, 2 * records / passes + 64));
    for (std::size_t pass = 0; pass < passes; ++pass) {
      const std::size_t first = pass * per_pass, last = first + per_pass;
      edges.clear();
      for (std::size_t f = 0; f < nf; ++f) {
        const auto& t = mesh.triangles[f];
        if (has_repeated_index(t)) continue;
        for (int c = 0; c < 3; ++c) {
          const std::int32_t a = t[c], b = t[(c + 1) % 3];
          const auto low = static_cast<std::size_t>(std::min(a, b));
          if (low >= first && low < last)
            edges.push_back({edge_key(a, b) << 1 | std::uint64_t{a < b}, static_cast<std::uint32_t>(f)});
        }
      }
      // By edge, then direction: the counts below do not depend on the order within a group.
      tbb::parallel_sort(edges.begin(), edges.end(),
                         [](const EdgeRecord& x, const EdgeRecord& y) { return x.key < y.key; });
      for (std::size_t i = 0; i < edges.size();) {
        std::size_t j = i + 1;
        while (j < edges.size() && edges[j].edge() == edges[i].edge()) ++j;
        const std::size_t n = j - i;
        ++topo.edges;
        if (n == 1) ++topo.boundary_edges;
        if (n > 2) ++topo.nonmanifold_edges;
        if (n == 2 && edges[i].forward() == edges[i + 1].forward()) ++topo.misoriented_edges;
        for (std::size_t k = i + 1; k < j; ++k) components.unite(edges[i].tri, edges[k].tri);
        i = j;
      }
    }
    for (std::size_t f = 0; f < nf; ++f)
      if (components.find(f) == f) ++topo.components;
  }

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
