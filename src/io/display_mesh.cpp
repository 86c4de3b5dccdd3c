#include "io/display_mesh.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>
#include <unordered_map>

namespace poreshell {
namespace {

TriangleMesh cluster(const TriangleMesh& mesh, const Vec3& origin, double cell,
                     std::vector<std::int32_t>& vertex_cell) {
  struct KeyHash {
    std::size_t operator()(const std::array<std::int64_t, 3>& k) const {
      return static_cast<std::size_t>(k[0] * 73856093 ^ k[1] * 19349663 ^ k[2] * 83492791);
    }
  };
  std::unordered_map<std::array<std::int64_t, 3>, std::int32_t, KeyHash> cell_index;
  cell_index.reserve(mesh.vertices.size() / 4);
  vertex_cell.resize(mesh.vertices.size());
  std::vector<Vec3> sum;
  std::vector<int> count;
  for (std::size_t v = 0; v < mesh.vertices.size(); ++v) {
    const Vec3 q = ((mesh.vertices[v] - origin) / cell).array().floor();
    const std::array<std::int64_t, 3> key{static_cast<std::int64_t>(q.x()), static_cast<std::int64_t>(q.y()),
                                          static_cast<std::int64_t>(q.z())};
    const auto [it, added] = cell_index.try_emplace(key, static_cast<std::int32_t>(sum.size()));
    if (added) {
      sum.push_back(Vec3::Zero());
      count.push_back(0);
    }
    vertex_cell[v] = it->second;
    sum[static_cast<std::size_t>(it->second)] += mesh.vertices[v];
    ++count[static_cast<std::size_t>(it->second)];
  }
  TriangleMesh out;
  out.vertices.resize(sum.size());
  for (std::size_t c = 0; c < sum.size(); ++c) out.vertices[c] = sum[c] / count[c];
  for (const auto& t : mesh.triangles) {
    const std::array<std::int32_t, 3> c{vertex_cell[static_cast<std::size_t>(t[0])],
                                        vertex_cell[static_cast<std::size_t>(t[1])],
                                        vertex_cell[static_cast<std::size_t>(t[2])]};
    if (!has_repeated_vertex(c)) out.triangles.push_back(c);
  }
  // The same cluster triangle from several input triangles: keep one (sorted corners as the key,
  // orientation from the first), keys made once rather than in every comparison.
  std::vector<std::pair<std::array<std::int32_t, 3>, std::size_t>> keyed(out.triangles.size());
  for (std::size_t i = 0; i < keyed.size(); ++i) {
    keyed[i] = {out.triangles[i], i};
    std::sort(keyed[i].first.begin(), keyed[i].first.end());
  }
  std::sort(keyed.begin(), keyed.end());
  std::vector<std::array<std::int32_t, 3>> unique;
  for (std::size_t i = 0; i < keyed.size(); ++i)
    if (i == 0 || keyed[i].first != keyed[i - 1].first) unique.push_back(out.triangles[keyed[i].second]);
  out.triangles = std::move(unique);
  return out;
}

}  // namespace

TriangleMesh reduce_for_display(const TriangleMesh& mesh, std::size_t max_triangles,
                                std::vector<std::int32_t>* shown_as) {
  if (mesh.triangles.size() <= max_triangles || mesh.vertices.empty()) {
    if (shown_as) {
      shown_as->resize(mesh.vertices.size());
      std::iota(shown_as->begin(), shown_as->end(), 0);
    }
    return mesh;
  }
  Vec3 lo = mesh.vertices.front(), hi = lo;
  for (const Vec3& v : mesh.vertices) {
    lo = lo.cwiseMin(v);
    hi = hi.cwiseMax(v);
  }
  const double area = surface_area(mesh);
  // A cell of side c holds about one vertex of the reduced surface, which has about 2 triangles a
  // vertex: area / c^2 vertices give 2 area / c^2 triangles.
  double cell = std::sqrt(2.0 * area / static_cast<double>(max_triangles));
  std::vector<std::int32_t> vertex_cell;
  for (;;) {
    TriangleMesh reduced = cluster(mesh, lo, cell, vertex_cell);
    if (reduced.triangles.size() <= max_triangles) {
      if (shown_as) *shown_as = std::move(vertex_cell);
      return reduced;
    }
    cell *= 1.2;
  }
}

}  // namespace poreshell
