#include "geometry/mesh_clean.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <limits>
#include <tuple>
#include <vector>

#include "core/error.hpp"

namespace poreshell {
namespace {

// A triangle's area counts as zero below 1e-14 of its longest edge squared, so a vertex placed absurdly
// far from the rest (1e16 mm from a 20 mm cube, or a float's 3.4e38) makes needles of all its triangles:
// dropping them would open a closed part with no word and hide the vertex from the size check (issue
// 47). Such a vertex, used by no kept triangle and outside the kept part's box by more than its
// diagonal, is refused by its index.
void refuse_far_thin_corners(const std::vector<Vec3>& vertices, const std::vector<std::int32_t>& imported,
                             const std::vector<std::array<std::int32_t, 3>>& kept,
                             const std::vector<std::int32_t>& thin_corners) {
  if (thin_corners.empty()) return;
  std::vector<char> in_kept(vertices.size(), 0);
  Vec3 low = Vec3::Constant(std::numeric_limits<double>::infinity()), high = -low;
  for (const auto& t : kept)
    for (const std::int32_t v : t) {
      in_kept[v] = 1;
      low = low.cwiseMin(vertices[v]);
      high = high.cwiseMax(vertices[v]);
    }
  const double reach = (high - low).norm();
  for (const std::int32_t v : thin_corners) {
    if (in_kept[v]) continue;
    const Vec3& p = vertices[v];
    const double outside = ((low - p).cwiseMax(0.0) + (p - high).cwiseMax(0.0)).maxCoeff();
    if (outside > reach)
      throw InputError(fmt::format(
          "vertex {} (counting from 0, as imported) at ({:.4g}, {:.4g}, {:.4g}) lies far outside the rest of "
          "the mesh (which spans ({:.4g}, {:.4g}, {:.4g}) to ({:.4g}, {:.4g}, {:.4g})), and its triangles "
          "are "
          "too thin to keep at that scale, so the part would lose them; remove or fix the vertex, or "
          "re-export the mesh",
          imported[v], p.x(), p.y(), p.z(), low.x(), low.y(), low.z(), high.x(), high.y(), high.z()));
  }
}

// Drops each triangle whose three vertices an earlier one has (either orientation), keeping the first;
// returns how many. A polygon fanned over a few coincident corners (a 4,000-vertex OBJ face over a cube's
// 8 corners) or an object placed many times at one spot gives thousands of coincident triangles that
// add nothing but make every later search slow (issue 47: 23 s for 4,000, a hang for 100,000).
std::int64_t drop_repeated_triangles(std::vector<std::array<std::int32_t, 3>>& triangles) {
  std::vector<std::array<std::int32_t, 4>> keys(triangles.size());  // sorted corners, then the index
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    std::array<std::int32_t, 3> c = triangles[t];
    std::sort(c.begin(), c.end());
    keys[t] = {c[0], c[1], c[2], static_cast<std::int32_t>(t)};
  }
  std::sort(keys.begin(), keys.end());
  std::vector<char> repeat(triangles.size(), 0);
  for (std::size_t i = 1; i < keys.size(); ++i)
    if (keys[i][0] == keys[i - 1][0] && keys[i][1] == keys[i - 1][1] && keys[i][2] == keys[i - 1][2])
      repeat[static_cast<std::size_t>(keys[i][3])] = 1;
  std::size_t kept = 0;
  for (std::size_t t = 0; t < triangles.size(); ++t)
    if (!repeat[t]) triangles[kept++] = triangles[t];
  const auto dropped = static_cast<std::int64_t>(triangles.size() - kept);
  triangles.resize(kept);
  return dropped;
}

}  // namespace

MeshInputStats clean_triangle_mesh(TriangleMesh& mesh) {
  const std::size_t nv = mesh.vertices.size();
  std::vector<char> used(nv, 0);
  for (std::size_t f = 0; f < mesh.triangles.size(); ++f)
    for (std::int32_t v : mesh.triangles[f]) {
      if (v < 0 || static_cast<std::size_t>(v) >= nv)
        throw InputError(
            fmt::format("triangle {} refers to vertex {}, but the mesh has {} vertices", f, v, nv));
      used[v] = 1;
    }
  std::vector<std::int32_t> order;
  for (std::size_t v = 0; v < nv; ++v) {
    if (!used[v]) continue;
    const Vec3& p = mesh.vertices[v];
    if (!p.allFinite())
      throw InputError(
          fmt::format("vertex {} (counting from 0, as imported) has a non-finite coordinate ({}, {}, {}) "
                      "(NaN or infinity): the file is corrupt; "
                      "repair or re-export the mesh",
                      v, p.x(), p.y(), p.z()));
    order.push_back(static_cast<std::int32_t>(v));
  }

  // Exact weld: sorting by position puts identical vertices next to each other.
  const auto less = [&](std::int32_t a, std::int32_t b) {
    const Vec3 &p = mesh.vertices[a], &q = mesh.vertices[b];
    return std::tie(p.x(), p.y(), p.z()) < std::tie(q.x(), q.y(), q.z());
  };
  std::stable_sort(order.begin(), order.end(), less);
  std::vector<std::int32_t> remap(nv, -1), imported;  // imported: a welded vertex's first index as read
  std::vector<Vec3> vertices;
  vertices.reserve(order.size());
  for (std::size_t i = 0; i < order.size(); ++i) {
    if (i == 0 || less(order[i - 1], order[i])) {
      vertices.push_back(mesh.vertices[order[i]]);
      imported.push_back(order[i]);
    }
    remap[order[i]] = static_cast<std::int32_t>(vertices.size() - 1);
  }

  MeshInputStats stats;
  std::vector<std::array<std::int32_t, 3>> triangles;
  triangles.reserve(mesh.triangles.size());
  std::vector<std::int32_t> thin_corners;  // corners of triangles dropped for their zero area
  for (const auto& t : mesh.triangles) {
    const std::array<std::int32_t, 3> r{remap[t[0]], remap[t[1]], remap[t[2]]};
    if (has_repeated_vertex(r) || zero_area(vertices[r[0]], vertices[r[1]], vertices[r[2]])) {
      if (!has_repeated_vertex(r)) thin_corners.insert(thin_corners.end(), r.begin(), r.end());
      ++stats.dropped_degenerate;
      continue;
    }
    triangles.push_back(r);
  }
  if (triangles.empty())
    throw InputError(
        fmt::format("the mesh has no usable triangles: all {} repeat a vertex or have zero area (collinear "
                    "corners); give a "
                    "mesh whose faces enclose some area",
                    stats.dropped_degenerate));
  refuse_far_thin_corners(vertices, imported, triangles, thin_corners);
  stats.dropped_duplicate = drop_repeated_triangles(triangles);
  // Drop vertices that only dropped triangles used.
  std::vector<std::int32_t> compact(vertices.size(), -1);
  mesh.vertices.clear();
  for (auto& t : triangles)
    for (std::int32_t& v : t) {
      if (compact[v] < 0) {
        compact[v] = static_cast<std::int32_t>(mesh.vertices.size());
        mesh.vertices.push_back(vertices[v]);
      }
      v = compact[v];
    }
  mesh.triangles = std::move(triangles);
  stats.vertices = static_cast<std::int64_t>(mesh.vertices.size());
  stats.triangles = static_cast<std::int64_t>(mesh.triangles.size());
  stats.boundary_edges = analyze_topology(mesh).boundary_edges;
  return stats;
}

}  // namespace poreshell
