#pragma once
// What the edge collapses of the triangle reduction (edge_collapse.hpp) are measured against: the
// original surface, as a corner table and as the test "is this point within the tolerance of it".

#include <algorithm>
#include <array>
#include <bit>
#include <cstdint>
#include <span>
#include <vector>

#include "geometry/mesh.hpp"
#include "geometry/mesh_surface.hpp"  // TriangleShape

namespace poreshell {

// Corner c is corner c % 3 of triangle c / 3.
inline std::int32_t next_corner(std::int32_t c) {
  return c % 3 == 2 ? c - 2 : c + 1;
}
inline std::int32_t previous_corner(std::int32_t c) {
  return c % 3 == 0 ? c + 2 : c - 1;
}

// For each corner of a closed, 2-manifold, consistently oriented mesh, the corner across the edge it
// faces: the other triangle's corner that faces the same edge.
// `around` is vertex_triangles() of the mesh, where the caller has it.
std::vector<std::int32_t> opposite_corners(const TriangleMesh& mesh, const VertexTriangles& around);
inline std::vector<std::int32_t> opposite_corners(const TriangleMesh& mesh) {
  return opposite_corners(mesh, vertex_triangles(mesh.vertices.size(), mesh.triangles));
}

// The original surface as the checks need it: vertex normals, and how near a point is. Every point
// asked about lies on a reduced triangle, whose corners are original vertices (the anchors): the
// searches start there and go across the original's edges, so they need no tree over the whole
// surface (building one for the bunny's 1.5 M-triangle shell took 0.7 s, a tenth of its reduction).
class OriginalSurface {
 public:
  // `opposite` is opposite_corners(mesh); both outlive this. `around` is vertex_triangles() of the mesh.
  OriginalSurface(const TriangleMesh& mesh, const std::vector<std::int32_t>& opposite,
                  VertexTriangles around);

  const Vec3& normal(std::int32_t v) const { return normals_[static_cast<std::size_t>(v)]; }

  // Whether p is within the tolerance of the original surface. Walks from the triangles around the
  // anchors across edges towards p while that comes closer, which settles nearly all (on the bunny
  // 95 %); else distance2_from() settles it. Never near where the surface is not.
  bool near(const Vec3& p, std::initializer_list<std::int32_t> anchors, double tolerance) const;

  // The squared distance from p to the original surface's sheet through the anchors: a best-first
  // search from the triangles around them, across edges, never into a triangle whose bounding sphere
  // is further than the nearest triangle found so far, and of at most kMaxVisits triangles. Never
  // less than the distance to the whole surface; equal to it unless another sheet comes nearer (the
  // far side of a wall thinner than the distance) or the search runs out. Stops once `enough2` is
  // reached.
  double distance2_from(const Vec3& p, std::initializer_list<std::int32_t> anchors,
                        double enough2 = 0.0) const;

 private:
  struct Bound {
    Vec3 center;
    double radius;  // of a sphere about center holding the triangle
    TriangleShape shape;
  };
  double gap(const Vec3& p, std::int32_t f) const;  // a lower bound on the distance to triangle f
  double distance2(const Vec3& p, std::int32_t f) const;
  std::span<const std::uint32_t> triangles_at(std::int32_t v) const {
    const auto x = static_cast<std::size_t>(v);
    return {around_.incident.data() + around_.start[x], around_.start[x + 1] - around_.start[x]};
  }

  const TriangleMesh& mesh_;
  const std::vector<std::int32_t>& opposite_;
  const VertexTriangles around_;
  std::vector<Bound> bounds_;
  std::vector<Vec3> normals_;
};

// Recent answers of OriginalSurface::near() for a triangle or an edge of original vertices: they
// never change for a given tolerance, and a vertex's collapses are rated again after every collapse
// next to it, asking many of the same questions. Direct-mapped and of bounded size: a miss costs the
// question, never a different answer.
class NearCache {
 public:
  explicit NearCache(std::size_t triangles)
      : slots_(std::min(std::bit_ceil(2 * triangles + 1), std::size_t{1} << 20)) {}

  // Triangle (a, b, c), or edge (a, b) with c = -1, in any order.
  template <class Ask>
  bool get(std::int32_t a, std::int32_t b, std::int32_t c, Ask&& ask) {
    std::array<std::int32_t, 3> key = {a, b, c};
    if (key[0] > key[1]) std::swap(key[0], key[1]);
    if (key[1] > key[2]) std::swap(key[1], key[2]);
    if (key[0] > key[1]) std::swap(key[0], key[1]);
    std::uint64_t h = 0x9e3779b97f4a7c15ull;
    for (const std::int32_t k : key) h = (h ^ static_cast<std::uint32_t>(k)) * 0xff51afd7ed558ccdull;
    Slot& slot = slots_[(h >> 32) & (slots_.size() - 1)];
    if (slot.key[0] != key[0] || slot.key[1] != key[1] || slot.key[2] != key[2]) {
      slot.key = key;
      slot.near = ask();
    }
    return slot.near;
  }

 private:
  struct Slot {
    std::array<std::int32_t, 3> key = {-2, -2, -2};
    bool near = false;
  };
  std::vector<Slot> slots_;
};

}  // namespace poreshell
