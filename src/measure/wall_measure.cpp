#include "measure/wall_measure.hpp"

// Each probe casts a ray both ways along its normal; its first hit on the mesh on each side gives the
// wall. Rays are hashed into cells along their segments, so each triangle is tested only against the
// rays that pass its cells: time is one pass over the triangles and memory a few kilobytes, however
// large the mesh (a search tree over a 24-million-triangle mesh would take 2 GB).
// Against Embree 3 (libembree-dev), bench/wall_rays_vs_embree.cpp: 256 rays across a 2.0 M-triangle
// spherical shell, 2 threads: this pass 0.27 s and 3.9 MB peak, Embree 2.47 s (BVH build; the rays take
// 0.3 ms) and 227 MB, both measuring the 0.2 wall; docs/benchmarks.md, "Wall probes against Embree".
// A BVH pays off only for many more rays than the probes cast.

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

#include <Eigen/Geometry>  // cross()
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "core/cell_hash.hpp"

namespace poreshell {
namespace {

constexpr double kNoHit = std::numeric_limits<double>::infinity();
constexpr std::int64_t kMaxCellsPerTriangle = 64;  // larger triangles are tested against every ray

struct Ray {
  Vec3 origin, direction;
};

// Distance along the ray to triangle (a, b, c) if it crosses it within [0, max_length] (Moller-Trumbore,
// both facings), else infinity.
double hit_distance(const Ray& ray, const Vec3& a, const Vec3& b, const Vec3& c, double max_length) {
  const Vec3 e1 = b - a, e2 = c - a;
  const Vec3 p = ray.direction.cross(e2);
  const double det = e1.dot(p);
  if (std::abs(det) < 1e-300) return kNoHit;  // parallel to the plane
  const double inv = 1.0 / det;
  const Vec3 s = ray.origin - a;
  const double u = s.dot(p) * inv;
  if (u < 0.0 || u > 1.0) return kNoHit;
  const Vec3 q = s.cross(e1);
  const double v = ray.direction.dot(q) * inv;
  if (v < 0.0 || u + v > 1.0) return kNoHit;
  const double t = e2.dot(q) * inv;
  return t >= 0.0 && t <= max_length ? t : kNoHit;
}

// Rays registered along their segments in cells of an eighth of their length: at points half a cell
// apart, with their neighbour cells, so every cell a segment passes is marked (a superset is harmless).
CellHash ray_cells(const std::vector<Ray>& rays, double max_length) {
  CellHash cells(max_length / 8.0);
  const int steps = 17;
  for (std::size_t r = 0; r < rays.size(); ++r)
    for (int s = 0; s < steps; ++s) {
      const Vec3 p = rays[r].origin + (max_length * s / (steps - 1)) * rays[r].direction;
      const std::int64_t i = cells.cell_of(p.x()), j = cells.cell_of(p.y()), k = cells.cell_of(p.z());
      for (int d = 0; d < 27; ++d)
        cells.add(i + d % 3 - 1, j + (d / 3) % 3 - 1, k + d / 9 - 1, static_cast<std::uint32_t>(r));
    }
  cells.seal();
  return cells;
}

}  // namespace

WallMeasurement measure_wall(const TriangleMesh& solid, std::span<const WallProbe> probes,
                             double max_length) {
  WallMeasurement m;
  if (probes.empty() || solid.triangles.empty() || !(max_length > 0.0)) return m;
  std::vector<Ray> rays;
  for (const WallProbe& p : probes) {
    rays.push_back({p.start, p.normal});
    rays.push_back({p.start, -p.normal});
  }
  const CellHash cells = ray_cells(rays, max_length);

  // Nearest hit per ray: a minimum, so the result does not depend on how the triangles are split.
  using Hits = std::vector<double>;
  const Hits nearest = tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(0, solid.triangles.size(), 4096), Hits(rays.size(), kNoHit),
      [&](const tbb::blocked_range<std::size_t>& range, Hits hits) {
        for (std::size_t f = range.begin(); f != range.end(); ++f) {
          const auto& t = solid.triangles[f];
          const Vec3& a = solid.vertices[static_cast<std::size_t>(t[0])];
          const Vec3& b = solid.vertices[static_cast<std::size_t>(t[1])];
          const Vec3& c = solid.vertices[static_cast<std::size_t>(t[2])];
          const auto test = [&](std::uint32_t r) {
            hits[r] = std::min(hits[r], hit_distance(rays[r], a, b, c, max_length));
          };
          const Vec3 lo = a.cwiseMin(b).cwiseMin(c), hi = a.cwiseMax(b).cwiseMax(c);
          const std::int64_t i0 = cells.cell_of(lo.x()), i1 = cells.cell_of(hi.x());
          const std::int64_t j0 = cells.cell_of(lo.y()), j1 = cells.cell_of(hi.y());
          const std::int64_t k0 = cells.cell_of(lo.z()), k1 = cells.cell_of(hi.z());
          if ((i1 - i0 + 1) * (j1 - j0 + 1) * (k1 - k0 + 1) > kMaxCellsPerTriangle) {
            for (std::uint32_t r = 0; r < rays.size(); ++r) test(r);
            continue;
          }
          for (std::int64_t i = i0; i <= i1; ++i)
            for (std::int64_t j = j0; j <= j1; ++j)
              for (std::int64_t k = k0; k <= k1; ++k) cells.for_each_in(i, j, k, test);
        }
        return hits;
      },
      [](Hits x, const Hits& y) {
        for (std::size_t r = 0; r < x.size(); ++r) x[r] = std::min(x[r], y[r]);
        return x;
      });

  std::vector<double> thickness;
  for (std::size_t p = 0; p < probes.size(); ++p) {
    const double up = nearest[2 * p], down = nearest[2 * p + 1];
    if (up < kNoHit && down < kNoHit) thickness.push_back(up + down);
  }
  if (thickness.empty()) return m;
  std::sort(thickness.begin(), thickness.end());
  m.probes = thickness.size();
  const auto percentile = [&](double q) {
    return thickness[static_cast<std::size_t>(q * static_cast<double>(thickness.size() - 1) + 0.5)];
  };
  m.median = thickness[thickness.size() / 2];
  m.min = thickness.front();
  m.max = thickness.back();
  m.low = percentile(0.05);
  m.high = percentile(0.95);
  m.merged = static_cast<std::size_t>(
      thickness.end() - std::upper_bound(thickness.begin(), thickness.end(), kMergedWall * m.median));
  return m;
}

}  // namespace poreshell
