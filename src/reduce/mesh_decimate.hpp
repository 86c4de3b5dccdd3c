#pragma once
// Optional reduction of a printable mesh's triangle count (--max-triangles). The result stays
// closed, 2-manifold and outward oriented, keeps its genus and components, has no degenerate
// triangles, and stays within a stated distance of the original surface; a result failing any of
// these is refused with an exception, never returned. New triangles have no angle below 10
// degrees, except where they replace a sharper one (isosurface slivers go away, none get worse).

#include <cstdint>
#include <optional>

#include "geometry/mesh.hpp"
#include "reduce/deviation_check.hpp"

namespace poreshell {

// How each collapse is kept within the distance bound: by a bound that follows from the triangles
// around it alone where one does (edge_collapse.cpp, fan_distance_bound()), else by asking the
// original surface at points; or by either alone, to compare (bench_reduce, tests).
// kBoundOnly reduces less (the bunny, 8 mm holes at 14 mm, 0.02 mm: 881 k triangles against 793 k) in one
// attempt that keeps the bound everywhere, where the checked collapses overshoot between their points and
// are redone with a smaller tolerance (there 45 s against 14 s). kPlaced moves the vertex a collapse keeps
// to where the quadrics are least and measures each collapse against the original directly
// (placed_collapse.hpp): at 0.02 mm the demo bunny's 2.1 M triangles go to 376 k where kBoundOnly leaves
// 724 k, the sphere r 50 mm's (6 mm holes at 10 mm) 1.15 M to 202 k against 339 k, for about five times
// the processor time (docs/benchmarks.md "Placed collapses").
enum class DistanceRule { kBoundOrCheck, kCheckOnly, kBoundOnly, kPlaced };

// A budget of at least this share of the input's triangles is tried by the fans' bounds first, which
// reach about a third (the demo bunny 0.34, the sphere r 50 mm 0.29 at 0.02 mm) at a fifth of a placed
// collapse's cost; where they stop short, the placed collapses go from the input as before.
inline constexpr double kBoundsFirstShare = 0.45;

struct DecimateOptions {
  std::int64_t max_triangles = 0;  // target count; >= 4
  // Bound on the distance between the reduced and the original surface, both ways, in the mesh's
  // units; > 0. Keep it well below half the thinnest wall, so that the two sides of a wall cannot
  // meet.
  double max_distance = 0.0;
  StageProgress progress{};  // the reduction's share of its stage (checked, reported)
  DistanceRule rule = DistanceRule::kBoundOrCheck;
};

// How many collapses each way of DistanceRule kept within the bound.
struct CollapseCounts {
  std::int64_t bounded = 0, checked = 0;
  CollapseCounts& operator+=(const CollapseCounts& other) {
    bounded += other.bounded;
    checked += other.checked;
    return *this;
  }
};

struct DecimateResult {
  std::int64_t triangles_before = 0, triangles_after = 0;
  // Measured afterwards, both ways: from the reduced mesh's edge midpoints and centroids to the
  // original surface's sheet through their triangle's corners (at least the distance to the whole
  // surface), and from the original vertices to the reduced triangle each was last distributed over
  // (at least the distance to the reduced surface, which is searched for only where that is over the
  // bound). Never above DecimateOptions::max_distance.
  double max_distance = 0.0;
  // Measured apart from the collapses' own points, by sampling both surfaces (deviation_check.hpp):
  // its max() too is never above DecimateOptions::max_distance.
  DeviationCheck sampled;
  bool reached_target = false;  // false when the distance bound or the triangle shapes stopped it first
  CollapseCounts collapses;     // of the attempt returned
  // Reductions made: more than 1 where the distance measured overshot, or where a budget tried by the
  // fans' bounds first (kBoundsFirstShare) was then reached by placed collapses.
  int attempts = 0;
  std::optional<MeshTopology> topology;  // of the reduced mesh, where the reduction ran (its check)
};

// Reduces `mesh` in place to at most options.max_triangles triangles, as far as the distance bound
// allows, by edge collapses onto existing vertices (every vertex kept is an original one; with kPlaced,
// moved to where the collapse puts it), in a deterministic order. The result's vertices are in Morton order,
// its triangles by their first vertex. A mesh with no more triangles than the target is left untouched.
// Throws InputError for bad options or a vertex coordinate that is not a finite number; std::runtime_error,
// leaving the mesh as it was, if the input is not a closed, manifold, outward oriented mesh without
// degenerate triangles or if the result fails a check.
DecimateResult decimate_mesh(TriangleMesh& mesh, const DecimateOptions& options);

}  // namespace poreshell
