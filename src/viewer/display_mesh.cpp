#include "viewer/display_mesh.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>
#include <unordered_map>

#include <Eigen/Geometry>

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
  const auto normal = [](const std::vector<Vec3>& points, const std::array<std::int32_t, 3>& t) {
    const Vec3& a = points[static_cast<std::size_t>(t[0])];
    return Vec3(
        (points[static_cast<std::size_t>(t[1])] - a).cross(points[static_cast<std::size_t>(t[2])] - a));
  };
  // Each cluster triangle with the input triangles it comes from, by its sorted corners (keys made once
  // rather than in every comparison).
  std::vector<std::pair<std::array<std::int32_t, 3>, std::size_t>> keyed;
  for (std::size_t f = 0; f < mesh.triangles.size(); ++f) {
    const auto& t = mesh.triangles[f];
    std::array<std::int32_t, 3> c{vertex_cell[static_cast<std::size_t>(t[0])],
                                  vertex_cell[static_cast<std::size_t>(t[1])],
                                  vertex_cell[static_cast<std::size_t>(t[2])]};
    if (has_repeated_vertex(c)) continue;
    std::sort(c.begin(), c.end());
    keyed.emplace_back(c, f);
  }
  std::sort(keyed.begin(), keyed.end());
  // Shown once, facing the way its input triangles face together: the first one's corners alone could
  // face into the part after clustering and show as a dark speck (the reduced bunny, 879 k triangles
  // with long thin ones at the rims, shown in 236 k: 2,256 shown triangles against their input's
  // normal, none with this). Where the input faces both ways about equally, a fold, the triangle is left out:
  // a gap smaller than a cell, which the viewer's two-sided faces hide.
  std::vector<std::array<std::int32_t, 3>> unique;
  for (std::size_t i = 0, next = 0; i < keyed.size(); i = next) {
    Vec3 facing = Vec3::Zero();
    double area = 0.0;
    for (next = i; next < keyed.size() && keyed[next].first == keyed[i].first; ++next) {
      const Vec3 n = normal(mesh.vertices, mesh.triangles[keyed[next].second]);
      facing += n;
      area += n.norm();
    }
    std::array<std::int32_t, 3> c = keyed[i].first;
    const double along = normal(out.vertices, c).normalized().dot(facing);
    if (std::abs(along) <= 0.1 * area) continue;
    if (along < 0.0) std::swap(c[1], c[2]);
    unique.push_back(c);
  }
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
