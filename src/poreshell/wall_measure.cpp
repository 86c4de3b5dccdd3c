#include "poreshell/wall_measure.hpp"

#include <algorithm>
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

}  // namespace

WallMeasurement measure_wall(const TriangleMesh& solid, std::span<const WallProbe> probes,
                             double max_length) {
  WallMeasurement m;
  if (probes.empty() || solid.triangles.empty()) return m;
  const MeshSurface surface(solid);
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
