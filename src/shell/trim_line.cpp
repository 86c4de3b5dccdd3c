#include "shell/trim_line.hpp"

#include <Eigen/Geometry>  // cross()
#include <algorithm>
#include <cmath>
#include <cstdint>

namespace poreshell {
namespace {

constexpr std::uint64_t edge_key(std::int32_t a, std::int32_t b) {
  const auto lo = static_cast<std::uint32_t>(std::min(a, b)), hi = static_cast<std::uint32_t>(std::max(a, b));
  return (std::uint64_t{lo} << 32) | hi;
}

}  // namespace

TrimLine::TrimLine(const TriangleMesh& mesh, double reach) : reach_(reach), cells_(reach) {
  // Each edge's triangle count and the triangle's third vertex (of the last triangle seen).
  struct Use {
    int count = 0;
    std::int32_t a = 0, b = 0, opposite = 0;
  };
  std::unordered_map<std::uint64_t, Use> uses;
  uses.reserve(3 * mesh.triangles.size() / 2 + 1);
  for (const Triangle& t : mesh.triangles) {
    if (has_repeated_vertex(t)) continue;
    for (int i = 0; i < 3; ++i) {
      Use& u = uses[edge_key(t[i], t[(i + 1) % 3])];
      ++u.count;
      u = {u.count, t[i], t[(i + 1) % 3], t[(i + 2) % 3]};
    }
  }
  std::vector<Use> open;
  for (const auto& [key, u] : uses)
    if (u.count == 1) open.push_back(u);
  // Hash order is not the input's: sort, so that the result does not depend on the library's hashing.
  std::sort(open.begin(), open.end(), [](const Use& p, const Use& q) {
    return std::make_pair(std::min(p.a, p.b), std::max(p.a, p.b)) <
           std::make_pair(std::min(q.a, q.b), std::max(q.a, q.b));
  });
  std::vector<Vec3> tangents;  // per open edge
  std::unordered_map<std::int32_t, Vec3> at_vertex;
  std::vector<Use> kept;
  for (const Use& u : open) {
    const Vec3 &a = mesh.vertices.at(static_cast<std::size_t>(u.a)),
               &b = mesh.vertices.at(static_cast<std::size_t>(u.b)),
               &c = mesh.vertices.at(static_cast<std::size_t>(u.opposite));
    if (zero_area(a, b, c)) continue;
    const Vec3 normal = (b - a).cross(c - a);
    Vec3 tau = (b - a).cross(normal).normalized();
    if (tau.dot(c - a) > 0.0) tau = -tau;  // away from the triangle
    tangents.push_back(tau);
    kept.push_back(u);
    for (std::int32_t v : {u.a, u.b}) {
      auto [it, fresh] = at_vertex.try_emplace(v, Vec3::Zero());
      it->second += tau;
    }
  }
  const auto vertex_tangent = [&](std::int32_t v, const Vec3& fallback) {
    const Vec3& sum = at_vertex.at(v);
    // Edges folding back on each other (a boundary doubling back) cancel: the edge's own tangent then.
    return sum.norm() > 1e-6 ? Vec3(sum.normalized()) : fallback;
  };
  edges_.reserve(kept.size());
  for (std::size_t i = 0; i < kept.size(); ++i) {
    const Use& u = kept[i];
    edges_.push_back({mesh.vertices[static_cast<std::size_t>(u.a)],
                      mesh.vertices[static_cast<std::size_t>(u.b)], vertex_tangent(u.a, tangents[i]),
                      vertex_tangent(u.b, tangents[i])});
  }
  if (!(reach_ > 0.0)) return;
  for (std::size_t i = 0; i < edges_.size(); ++i) {
    const TrimEdge& e = edges_[i];
    cells_.add_box(e.a.cwiseMin(e.b) - Vec3::Constant(reach_), e.a.cwiseMax(e.b) + Vec3::Constant(reach_),
                   static_cast<std::uint32_t>(i));
  }
  cells_.seal();
}

std::optional<double> TrimLine::beyond(const Vec3& x) const {
  if (edges_.empty() || !(reach_ > 0.0)) return std::nullopt;  // no edge is registered
  double best = reach_ * reach_;
  const TrimEdge* nearest = nullptr;
  double at = 0.0;
  // Ties go to the later edge, as the cell lists edges in ascending order.
  cells_.for_each_at(x, [&](std::uint32_t i) {
    const TrimEdge& e = edges_[i];
    const Vec3 ab = e.b - e.a;
    const double len2 = ab.squaredNorm();
    const double u = len2 > 0.0 ? std::clamp((x - e.a).dot(ab) / len2, 0.0, 1.0) : 0.0;
    const double d2 = (x - (e.a + u * ab)).squaredNorm();
    if (d2 <= best) {
      best = d2;
      nearest = &e;
      at = u;
    }
  });
  if (nearest == nullptr) return std::nullopt;
  const Vec3 b = nearest->a + at * (nearest->b - nearest->a);
  const Vec3 mixed = (1.0 - at) * nearest->tangent_a + at * nearest->tangent_b;
  const Vec3 tau = mixed.norm() > 1e-6 ? Vec3(mixed.normalized()) : nearest->tangent_a;
  return (x - b).dot(tau);
}

}  // namespace poreshell
