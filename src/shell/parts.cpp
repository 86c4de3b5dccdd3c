#include "shell/parts.hpp"

#include <Eigen/Geometry>  // cross()
#include <algorithm>
#include <cmath>
#include <vector>

#include "core/disjoint_sets.hpp"

namespace poreshell {

PartsSummary keep_main_parts(TriangleMesh& mesh, double min_fraction, bool fill_cavities) {
  PartsSummary summary;
  DisjointSets parts(mesh.vertices.size());
  for (const auto& t : mesh.triangles)
    for (int k = 1; k < 3; ++k) parts.unite(t[0], t[static_cast<std::size_t>(k)]);
  // Signed volume per component (divergence theorem over its triangles).
  std::vector<double> volume(mesh.vertices.size(), 0.0);
  std::vector<std::int32_t> component(mesh.triangles.size());
  for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
    const auto& t = mesh.triangles[i];
    component[i] = parts.find(t[0]);
    const Vec3 &a = mesh.vertices[static_cast<std::size_t>(t[0])],
               &b = mesh.vertices[static_cast<std::size_t>(t[1])],
               &c = mesh.vertices[static_cast<std::size_t>(t[2])];
    volume[static_cast<std::size_t>(component[i])] += a.dot(b.cross(c)) / 6.0;
  }
  double largest = 0.0;
  for (double v : volume) largest = std::max(largest, std::abs(v));
  const double threshold = min_fraction * largest;
  std::vector<char> keep(mesh.vertices.size(), 0), seen(mesh.vertices.size(), 0);
  for (std::int32_t root : component) {
    const auto r = static_cast<std::size_t>(root);
    if (seen[r]) continue;
    seen[r] = 1;
    if (std::abs(volume[r]) >= threshold && volume[r] > 0.0) {
      keep[r] = 1;
      ++summary.parts;
      continue;
    }
    // Inward components at or above the threshold: kept as the shell's own inside, or filled. Not among
    // `voids`: the wall without pores has no such pocket of its own (it is part of its one inside).
    if (volume[r] < 0.0 && std::abs(volume[r]) >= threshold) {
      if (!fill_cavities) {
        keep[r] = 1;
        continue;
      }
      ++summary.filled_cavities;
      summary.filled_volume += std::abs(volume[r]);
      summary.largest_filled_volume = std::max(summary.largest_filled_volume, std::abs(volume[r]));
      continue;
    }
    ++(volume[r] < 0.0 ? summary.removed_voids : summary.removed_fragments);
    summary.removed_volume += std::abs(volume[r]);
    summary.largest_removed_volume = std::max(summary.largest_removed_volume, std::abs(volume[r]));
  }
  if (summary.removed_fragments + summary.removed_voids + summary.filled_cavities == 0) return summary;
  // The removed voids' vertices, triangles (closed: E = 3F/2, so chi = V - F/2) and centroids.
  std::vector<std::int32_t> void_of(mesh.vertices.size(), -1);  // by root
  for (const std::int32_t root : component) {
    const auto r = static_cast<std::size_t>(root);
    if (keep[r] || volume[r] >= 0.0 || std::abs(volume[r]) >= threshold || void_of[r] >= 0) continue;
    void_of[r] = static_cast<std::int32_t>(summary.voids.size());
    summary.voids.emplace_back();
  }
  std::vector<std::int64_t> void_vertices(summary.voids.size(), 0);
  for (std::size_t v = 0; v < mesh.vertices.size(); ++v)
    if (const std::int32_t i = void_of[static_cast<std::size_t>(parts.find(static_cast<std::int32_t>(v)))];
        i >= 0) {
      ++void_vertices[static_cast<std::size_t>(i)];
      summary.voids[static_cast<std::size_t>(i)].inside += mesh.vertices[v];
    }
  std::vector<std::int64_t> void_triangles(summary.voids.size(), 0);
  for (const std::int32_t root : component)
    if (const std::int32_t i = void_of[static_cast<std::size_t>(root)]; i >= 0)
      ++void_triangles[static_cast<std::size_t>(i)];
  for (std::size_t i = 0; i < summary.voids.size(); ++i) {
    summary.voids[i].inside /= static_cast<double>(void_vertices[i]);
    summary.voids[i].euler_characteristic = void_vertices[i] - void_triangles[i] / 2;
  }
  // Keep the triangles of kept components, then drop the vertices no triangle uses (order kept).
  std::vector<std::array<std::int32_t, 3>> triangles;
  triangles.reserve(mesh.triangles.size());
  for (std::size_t i = 0; i < mesh.triangles.size(); ++i)
    if (keep[static_cast<std::size_t>(component[i])]) triangles.push_back(mesh.triangles[i]);
  std::vector<std::int32_t> index(mesh.vertices.size(), -1);
  for (const auto& t : triangles)
    for (std::int32_t v : t) index[static_cast<std::size_t>(v)] = 0;
  std::vector<Vec3> vertices;
  for (std::size_t v = 0; v < mesh.vertices.size(); ++v)
    if (index[v] == 0) {
      index[v] = static_cast<std::int32_t>(vertices.size());
      vertices.push_back(mesh.vertices[v]);
    }
  for (auto& t : triangles)
    for (std::int32_t& v : t) v = index[static_cast<std::size_t>(v)];
  mesh.vertices = std::move(vertices);
  mesh.triangles = std::move(triangles);
  return summary;
}

}  // namespace poreshell
