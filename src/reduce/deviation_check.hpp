#pragma once
// The two-sided distance between a reduced mesh and the mesh it was reduced from, measured by
// sampling both surfaces (issue 49): independent of how the reduction bounded its own collapses, so
// that the figure in the report is one the reduction did not choose its points for. Points are spread
// over each surface by area from a fixed seed (the same points on any number of threads); each point's
// distance to the other surface is exact (MeshSurface). (Four points in every reduced triangle as well
// took the bunny's check from about 1 s to 12 s: the reduction checks its centroids and edge midpoints
// already.)

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "geometry/mesh.hpp"
#include "geometry/mesh_surface.hpp"

namespace poreshell {

struct DeviationCheck {
  double reduced_to_full = 0.0;  // largest distance from the reduced surface's points to the full one
  double full_to_reduced = 0.0;  // and back
  std::int64_t samples = 0;      // points measured, both ways together
  double max() const { return reduced_to_full > full_to_reduced ? reduced_to_full : full_to_reduced; }
};

inline constexpr std::int64_t kDeviationSamplesPerSide = 100000;

// `full` and `reduced` in the same frame. Throws InputError where either has no triangle of nonzero area.
DeviationCheck check_deviation(const TriangleMesh& full, const TriangleMesh& reduced,
                               std::int64_t samples_per_side = kDeviationSamplesPerSide,
                               std::uint64_t seed = 49);

// A point spread by area over triangles, and the triangle it lies on.
struct SurfaceSample {
  Vec3 point;
  std::size_t triangle = 0;
};
// `count` points over `triangles` (indices into `vertices`) by area, from `seed`: the same points on any
// number of threads. Throws InputError where the triangles have no area.
std::vector<SurfaceSample> area_samples(std::span<const Vec3> vertices,
                                        std::span<const std::array<std::int32_t, 3>> triangles,
                                        std::int64_t count, std::uint64_t seed);
// The seed of the second side's points, from the first's.
std::uint64_t other_side_seed(std::uint64_t seed);

}  // namespace poreshell
