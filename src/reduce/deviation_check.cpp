#include "reduce/deviation_check.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

#include <Eigen/Geometry>  // cross()
#include <algorithm>
#include <vector>

#include "core/error.hpp"
#include "core/splitmix.hpp"

namespace poreshell {
namespace {

double unit(std::uint64_t x) {
  return static_cast<double>(x >> 11) * 0x1.0p-53;
}

}  // namespace

std::vector<SurfaceSample> area_samples(std::span<const Vec3> vertices,
                                        std::span<const std::array<std::int32_t, 3>> triangles,
                                        std::int64_t count, std::uint64_t seed) {
  std::vector<double> cumulative(triangles.size());
  double total = 0.0;
  for (std::size_t f = 0; f < triangles.size(); ++f) {
    const auto& t = triangles[f];
    const Vec3 &a = vertices[static_cast<std::size_t>(t[0])], &b = vertices[static_cast<std::size_t>(t[1])],
               &c = vertices[static_cast<std::size_t>(t[2])];
    total += 0.5 * (b - a).cross(c - a).norm();
    cumulative[f] = total;
  }
  if (!(total > 0.0)) throw InputError("the mesh to measure the deviation on has no area");
  std::vector<SurfaceSample> samples(static_cast<std::size_t>(count));
  for (std::int64_t i = 0; i < count; ++i) {
    const std::uint64_t r = splitmix64(seed ^ splitmix64(static_cast<std::uint64_t>(i)));
    const double at = unit(r) * total;
    const auto f = static_cast<std::size_t>(std::min<std::ptrdiff_t>(
        std::upper_bound(cumulative.begin(), cumulative.end(), at) - cumulative.begin(),
        static_cast<std::ptrdiff_t>(cumulative.size()) - 1));
    double u = unit(splitmix64(r + 1)), v = unit(splitmix64(r + 2));
    if (u + v > 1.0) u = 1.0 - u, v = 1.0 - v;  // fold into the triangle: uniform over it
    const auto& t = triangles[f];
    const Vec3 &a = vertices[static_cast<std::size_t>(t[0])], &b = vertices[static_cast<std::size_t>(t[1])],
               &c = vertices[static_cast<std::size_t>(t[2])];
    samples[static_cast<std::size_t>(i)] = {a + u * (b - a) + v * (c - a), f};
  }
  return samples;
}

std::uint64_t other_side_seed(std::uint64_t seed) {
  return splitmix64(seed);
}

namespace {

// The largest distance from `points` to `surface`: a maximum, the same in any order.
double largest_distance(const std::vector<SurfaceSample>& points, const MeshSurface& surface) {
  return tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(0, points.size()), 0.0,
      [&](const tbb::blocked_range<std::size_t>& r, double d) {
        for (std::size_t i = r.begin(); i != r.end(); ++i) d = std::max(d, surface.distance(points[i].point));
        return d;
      },
      [](double a, double b) { return std::max(a, b); });
}

}  // namespace

DeviationCheck check_deviation(const TriangleMesh& full, const TriangleMesh& reduced,
                               std::int64_t samples_per_side, std::uint64_t seed) {
  DeviationCheck check;
  check.reduced_to_full = largest_distance(
      area_samples(reduced.vertices, reduced.triangles, samples_per_side, seed), MeshSurface(full));
  check.full_to_reduced =
      largest_distance(area_samples(full.vertices, full.triangles, samples_per_side, other_side_seed(seed)),
                       MeshSurface(reduced));
  check.samples = 2 * samples_per_side;
  return check;
}

}  // namespace poreshell
