#pragma once
// Indexed triangle mesh and the topology checks a printable output must pass.

#include <Eigen/Geometry>  // cross()
#include <algorithm>
#include <array>
#include <cstdint>
#include <vector>

#include "core/run_monitor.hpp"
#include "core/types.hpp"

namespace poreshell {

struct TriangleMesh {
  std::vector<Vec3> vertices;
  std::vector<std::array<std::int32_t, 3>> triangles;  // counter-clockwise seen from outside
};

struct MeshTopology {
  std::int64_t vertices = 0, edges = 0, triangles = 0;
  std::int64_t boundary_edges = 0;        // edges with one triangle
  std::int64_t nonmanifold_edges = 0;     // edges with more than two triangles
  std::int64_t nonmanifold_vertices = 0;  // vertices whose triangle fan is not a single disc
  std::int64_t misoriented_edges = 0;     // interior edges traversed in the same direction by both triangles
  std::int64_t degenerate_triangles = 0;  // zero area or repeated vertex
  std::int64_t components = 0;            // connected components (by shared edges)
  std::int64_t euler_characteristic = 0;  // V - E + F
  double signed_volume = 0.0;             // positive when outward oriented
  double min_angle_degrees = 0.0;         // smallest triangle angle (slivers: under about 1 degree)
  bool closed() const { return boundary_edges == 0; }
  bool manifold() const { return nonmanifold_edges == 0 && nonmanifold_vertices == 0; }
  bool oriented() const { return misoriented_edges == 0; }
};

using Triangle = std::array<std::int32_t, 3>;
using Edge = std::array<std::int32_t, 2>;

// Square of the sine of the smallest angle, (2 area * shortest edge / (product of the edges))^2: 0 for
// a degenerate triangle, 3/4 for an equilateral one, whatever the scale. Squared and inline, it needs
// no root and no call: the reduction asks it for every triangle it would make, the isosurface for every
// triangle it makes. `cross` is
// (b - a) x (c - a), where the caller has it already.
inline double min_angle_sine_squared(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& cross) {
  const double ab = (b - a).squaredNorm(), bc = (c - b).squaredNorm(), ca = (a - c).squaredNorm();
  const double product = ab * bc * ca;
  if (!(product > 0.0)) return 0.0;
  return cross.squaredNorm() * std::min({ab, bc, ca}) / product;
}
inline double min_angle_sine_squared(const Vec3& a, const Vec3& b, const Vec3& c) {
  return min_angle_sine_squared(a, b, c, (b - a).cross(c - a));
}

// The degenerate-triangle rule (a repeated vertex index, or zero area), one for the input's cleaning, the
// topology check, the closest-point search and the decimater.
inline bool has_repeated_vertex(const Triangle& t) {
  return t[0] == t[1] || t[1] == t[2] || t[0] == t[2];
}
// Where v is in t, a triangle of v's (its first place; 2 where v is not in it).
inline int place_of(const Triangle& t, std::int32_t v) {
  return t[0] == v ? 0 : (t[1] == v ? 1 : 2);
}
// Twice the area and the longest edge squared, which the shape tests compare.
struct TriangleSize {
  double twice_area = 0.0, longest2 = 0.0;
  // Zero area: collinear up to round-off (a few ulps of the longest edge, whatever the model's units).
  // NaN coordinates count as zero area.
  bool zero_area() const { return !(twice_area > 1e-14 * longest2); }
};
TriangleSize triangle_size(const Vec3& a, const Vec3& b, const Vec3& c);
inline bool zero_area(const Vec3& a, const Vec3& b, const Vec3& c) {
  return triangle_size(a, b, c).zero_area();
}
bool is_degenerate(const TriangleMesh& mesh, const Triangle& t);

// The sum of the triangles' areas, in order.
double surface_area(const TriangleMesh& mesh);

// Edges with one triangle (triangles with a repeated vertex left out), each as (smaller vertex, larger),
// ascending: the open boundary. analyze_topology counts the same edges in the same pass.
std::vector<Edge> boundary_edges(std::size_t vertex_count, const std::vector<Triangle>& triangles);
inline std::vector<Edge> boundary_edges(const TriangleMesh& mesh) {
  return boundary_edges(mesh.vertices.size(), mesh.triangles);
}

// The triangles at each vertex (triangles with a repeated index left out), as compressed rows: the
// triangles of v are incident[start[v] .. start[v + 1]), ascending. Indices must be in range.
struct VertexTriangles {
  std::vector<std::uint32_t> start;
  std::vector<std::uint32_t> incident;
};
VertexTriangles vertex_triangles(std::size_t vertex_count, const std::vector<Triangle>& triangles);

// Throws std::out_of_range, its message starting with `what`, for a vertex index outside 0 .. vertex_count.
void check_vertex_indices(std::size_t vertex_count, const std::vector<Triangle>& triangles, const char* what);

// Throws std::out_of_range for a vertex index outside the mesh. The result does not depend on the order
// of the triangles or the thread count.
MeshTopology analyze_topology(const TriangleMesh& mesh, const StageProgress& progress = {});
// The same with the mesh's vertex_triangles(), where the caller has them (so its indices are in range).
MeshTopology analyze_topology(const TriangleMesh& mesh, const VertexTriangles& around,
                              const StageProgress& progress = {});

}  // namespace poreshell
