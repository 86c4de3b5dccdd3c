#include "geometry/refine.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <unordered_map>

namespace poreshell {
namespace {

std::uint64_t edge_key(std::int32_t a, std::int32_t b) {
  const auto lo = static_cast<std::uint32_t>(std::min(a, b)), hi = static_cast<std::uint32_t>(std::max(a, b));
  return (std::uint64_t{lo} << 32) | hi;
}

// One round: the midpoints of the long edges, then each triangle cut by its split edges. Returns false,
// leaving the mesh as it was, when no edge is long or the round would pass the budget.
bool split_round(TriangleMesh& mesh, double longest2, std::size_t max_triangles) {
  const std::size_t vertex_count = mesh.vertices.size();
  std::size_t added_triangles = 0;  // one per split edge of each triangle
  std::unordered_map<std::uint64_t, std::int32_t> midpoint;
  // mid[t][k]: the midpoint of edge k (from corner k to k + 1) of triangle t, or -1.
  std::vector<std::array<std::int32_t, 3>> mid(mesh.triangles.size(), {-1, -1, -1});
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const Triangle& tri = mesh.triangles[t];
    if (has_repeated_vertex(tri)) continue;
    for (std::size_t k = 0; k < 3; ++k) {
      const std::int32_t a = tri[k], b = tri[(k + 1) % 3];
      const Vec3& pa = mesh.vertices[static_cast<std::size_t>(a)];
      const Vec3& pb = mesh.vertices[static_cast<std::size_t>(b)];
      if ((pa - pb).squaredNorm() <= longest2) continue;
      const auto [it, added] =
          midpoint.try_emplace(edge_key(a, b), static_cast<std::int32_t>(mesh.vertices.size()));
      if (added) mesh.vertices.push_back(0.5 * (pa + pb));
      mid[t][k] = it->second;
      ++added_triangles;
    }
  }
  if (midpoint.empty() || mesh.triangles.size() + added_triangles > max_triangles) {
    mesh.vertices.resize(vertex_count);
    return false;
  }
  std::vector<Triangle> out;
  out.reserve(mesh.triangles.size() + 3 * midpoint.size());
  const auto length2 = [&](std::int32_t a, std::int32_t b) {
    return (mesh.vertices[static_cast<std::size_t>(a)] - mesh.vertices[static_cast<std::size_t>(b)])
        .squaredNorm();
  };
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const Triangle& tri = mesh.triangles[t];
    const auto& m = mid[t];
    const int splits = (m[0] >= 0) + (m[1] >= 0) + (m[2] >= 0);
    if (splits == 0) {
      out.push_back(tri);
    } else if (splits == 3) {
      out.push_back({tri[0], m[0], m[2]});
      out.push_back({m[0], tri[1], m[1]});
      out.push_back({m[2], m[1], tri[2]});
      out.push_back({m[0], m[1], m[2]});
    } else {
      // Rotate so that edge 0 (corners a -> b) is split, and for two splits edge 1 (b -> c) too.
      std::size_t r = 0;
      if (splits == 1)
        while (m[r] < 0) ++r;
      else
        while (!(m[r] >= 0 && m[(r + 1) % 3] >= 0)) ++r;
      const std::int32_t a = tri[r], b = tri[(r + 1) % 3], c = tri[(r + 2) % 3];
      const std::int32_t ab = m[r], bc = m[(r + 1) % 3];
      if (splits == 1) {
        out.push_back({a, ab, c});
        out.push_back({ab, b, c});
      } else {
        out.push_back({ab, b, bc});
        // The quad a, ab, bc, c along its shorter diagonal.
        if (length2(a, bc) <= length2(ab, c)) {
          out.push_back({a, ab, bc});
          out.push_back({a, bc, c});
        } else {
          out.push_back({a, ab, c});
          out.push_back({ab, bc, c});
        }
      }
    }
  }
  mesh.triangles = std::move(out);
  return true;
}

}  // namespace

TriangleMesh split_long_edges(TriangleMesh mesh, double longest, std::size_t max_triangles) {
  constexpr int kMostRounds = 32;  // each round halves the long edges: 2^32 times the length asked
  for (int round = 0; round < kMostRounds; ++round)
    if (!split_round(mesh, longest * longest, max_triangles)) break;
  return mesh;
}

TriangleMesh preview_surface_mesh(const TriangleMesh& mesh, double h) {
  constexpr std::size_t kTriangleBudget = 2'000'000;
  return split_long_edges(mesh, std::sqrt(2.0) * h, std::max(kTriangleBudget, mesh.triangles.size()));
}

}  // namespace poreshell
