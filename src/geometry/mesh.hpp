#pragma once
// Indexed triangle mesh and the topology checks a printable output must pass.

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

// Throws std::out_of_range for a vertex index outside the mesh. The result does not depend on the order
// of the triangles or the thread count.
MeshTopology analyze_topology(const TriangleMesh& mesh, const StageProgress& progress = {});

}  // namespace poreshell
