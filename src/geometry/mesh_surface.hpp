#pragma once
// A triangle mesh as a Surface: exact unsigned distance and closest point from a bounding-volume
// hierarchy over its triangles. Unsigned, so open surfaces and scans with holes need no repair.

#include <cstdint>
#include <limits>
#include <optional>
#include <vector>

#include "geometry/mesh.hpp"
#include "geometry/surface.hpp"

namespace poreshell {

// How a triangle's closest point is computed: by Voronoi regions, also checking the edges where the
// region tests lose digits (sliver), or from the edges alone (zero area).
enum class TriangleShape : std::uint8_t { regular, sliver, degenerate };
TriangleShape classify_triangle(const Vec3& a, const Vec3& b, const Vec3& c);

// Closest point to p on triangle (a, b, c), robust for zero-area and sliver triangles.
Vec3 closest_point_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);
Vec3 closest_point_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c,
                               TriangleShape shape);

class MeshSurface final : public Surface {
 public:
  // Triangles with a repeated vertex index are skipped. Throws InputError if none is left.
  explicit MeshSurface(const TriangleMesh& mesh);

  double distance(const Vec3& p) const override;  // unsigned
  std::optional<Vec3> closest_point(const Vec3& p) const override;
  bool closest_point_is_exact() const override { return true; }
  SurfaceQuery distance_and_closest_point(const Vec3& p) const override;  // one search
  SurfaceQuery distance_and_closest_point_near(const Vec3& p, const Vec3& on_surface) const override;
  double distance_up_to(const Vec3& p, double bound) const override;
  Box bounds() const override;
  std::string name() const override { return "mesh"; }

  std::size_t triangle_count() const { return tris_.size(); }

  // The nearest triangle, as its index in the constructor's mesh.triangles (a skipped triangle is
  // never nearest), and the closest point on it: what interpolating per-vertex data needs.
  struct NearestTriangle {
    std::size_t triangle = 0;
    Vec3 point = Vec3::Zero();
  };
  NearestTriangle nearest_triangle(const Vec3& p) const;
  // The same where a triangle comes within `reach` of p, else nothing (a search that stops at reach).
  std::optional<NearestTriangle> nearest_triangle_within(const Vec3& p, double reach) const;

 private:
  struct Node {
    Vec3 lo = Vec3::Zero(), hi = Vec3::Zero();
    std::int32_t first = 0;  // leaf: first triangle; inner: left child (right child is first + 1)
    std::int32_t count = 0;  // leaf: number of triangles; inner: 0
  };
  struct Tri {
    Vec3 a, b, c;
    TriangleShape shape = TriangleShape::regular;
    Vec3 centre = Vec3::Zero();  // of a sphere around the triangle: a cheap lower bound on its distance
    double radius = 0.0;
  };

  // Fills nodes[node] for the triangles order[begin, end), split by surface area (split_by_area)
  // above depth kSahDepth, at the centroids' median below it or where that split fails, and appends
  // its descendants to `nodes`.
  static void build(std::vector<Node>& nodes, std::int32_t node, std::vector<std::int32_t>& order,
                    const std::vector<Tri>& tris, const std::vector<Vec3>& centroids, std::int32_t begin,
                    std::int32_t end, int depth);
  static std::int32_t split_by_area(std::vector<std::int32_t>& order, const std::vector<Tri>& tris,
                                    const std::vector<Vec3>& centroids, std::int32_t begin, std::int32_t end,
                                    int axis, const Vec3& clo, const Vec3& chi);
  // Squared distance, closest point and position in tris_ of the nearest triangle; with a finite
  // `bound2`, only triangles nearer than its root are searched (infinity where there is none).
  double nearest(const Vec3& p, Vec3& closest, std::int32_t& index,
                 double bound2 = std::numeric_limits<double>::infinity()) const;

  std::vector<Node> nodes_;                // nodes_[0] is the root
  std::vector<Tri> tris_;                  // in leaf order, so a leaf's triangles are contiguous
  std::vector<std::int32_t> input_index_;  // of tris_[i] in the constructor's mesh.triangles
};

}  // namespace poreshell
