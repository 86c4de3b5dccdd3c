#include "poreshell/wall_measure.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <vector>

#include "poreshell/mesh_surface.hpp"

namespace poreshell {
namespace {

// Distance along the ray to the surface: steps of the distance to the nearest triangle never cross
// it; stops within `tolerance` of it or gives up beyond `max_length`.
std::optional<double> trace(const MeshSurface& surface, const Vec3& start, const Vec3& direction,
                            double max_length, double tolerance) {
  double s = 0.0;
  for (int i = 0; i < 200 && s <= max_length; ++i) {
    const double d = surface.distance(start + s * direction);
    if (d < tolerance) return s;
    s += d;
  }
  return std::nullopt;
}

// The triangles that can matter to the probes: those whose box meets a cell (of side 2 reach) that a
// probe's segment, grown by reach, meets. A triangle left out is farther than reach from every point
// a trace visits, so each step, hit and miss is the same as with the whole mesh; the tree is built over
// the probes' neighbourhoods instead of millions of triangles (about 100 bytes each).
TriangleMesh triangles_near(const TriangleMesh& solid, std::span<const WallProbe> probes, double reach) {
  const double cell = 2.0 * reach;
  const auto cell_of = [&](double x) { return static_cast<std::int64_t>(std::floor(x / cell)); };
  const auto key = [](std::int64_t i, std::int64_t j, std::int64_t k) {
    return ((i & 0x1FFFFF) << 42) | ((j & 0x1FFFFF) << 21) | (k & 0x1FFFFF);  // wraps: only more cells
  };
  std::vector<std::int64_t> marked;
  for (const WallProbe& p : probes) {
    const Vec3 a = p.start - reach * p.normal, b = p.start + reach * p.normal;
    const Vec3 lo = a.cwiseMin(b) - Vec3::Constant(reach), hi = a.cwiseMax(b) + Vec3::Constant(reach);
    for (std::int64_t i = cell_of(lo.x()); i <= cell_of(hi.x()); ++i)
      for (std::int64_t j = cell_of(lo.y()); j <= cell_of(hi.y()); ++j)
        for (std::int64_t k = cell_of(lo.z()); k <= cell_of(hi.z()); ++k) marked.push_back(key(i, j, k));
  }
  std::sort(marked.begin(), marked.end());
  marked.erase(std::unique(marked.begin(), marked.end()), marked.end());
  TriangleMesh near;
  for (const auto& t : solid.triangles) {
    const Vec3 &a = solid.vertices[static_cast<std::size_t>(t[0])],
               &b = solid.vertices[static_cast<std::size_t>(t[1])],
               &c = solid.vertices[static_cast<std::size_t>(t[2])];
    const Vec3 lo = a.cwiseMin(b).cwiseMin(c), hi = a.cwiseMax(b).cwiseMax(c);
    bool hit = false;
    for (std::int64_t i = cell_of(lo.x()); i <= cell_of(hi.x()) && !hit; ++i)
      for (std::int64_t j = cell_of(lo.y()); j <= cell_of(hi.y()) && !hit; ++j)
        for (std::int64_t k = cell_of(lo.z()); k <= cell_of(hi.z()) && !hit; ++k)
          hit = std::binary_search(marked.begin(), marked.end(), key(i, j, k));
    if (!hit) continue;
    const auto first = static_cast<std::int32_t>(near.vertices.size());
    near.vertices.insert(near.vertices.end(), {a, b, c});
    near.triangles.push_back({first, first + 1, first + 2});
  }
  return near;
}

}  // namespace

WallMeasurement measure_wall(const TriangleMesh& solid, std::span<const WallProbe> probes,
                             double max_length) {
  WallMeasurement m;
  if (probes.empty() || solid.triangles.empty()) return m;
  const TriangleMesh near = triangles_near(solid, probes, max_length);
  if (near.triangles.empty()) return m;  // nothing within reach: no probe can meet the surface
  const MeshSurface surface(near);
  const double tolerance = 1e-6 * max_length;
  std::vector<double> thickness;
  for (const WallProbe& p : probes) {
    const auto up = trace(surface, p.start, p.normal, max_length, tolerance);
    const auto down = trace(surface, p.start, -p.normal, max_length, tolerance);
    if (up && down) thickness.push_back(*up + *down);
  }
  if (thickness.empty()) return m;
  std::sort(thickness.begin(), thickness.end());
  m.probes = thickness.size();
  m.median = thickness[thickness.size() / 2];
  m.min = thickness.front();
  m.max = thickness.back();
  return m;
}

}  // namespace poreshell
