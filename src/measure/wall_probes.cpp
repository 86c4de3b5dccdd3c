#include "measure/wall_probes.hpp"

#include <algorithm>

#include "core/error.hpp"
#include "pattern/solid_zones.hpp"
#include "shell/trim_line.hpp"

namespace poreshell {

void make_side_test(WallOffset offset, const PlacedSurface& placed, double h, SideTest& test) {
  if (offset == WallOffset::centered || placed.input.kind == "shape") return;
  if (!placed.mesh)
    throw OptionError("offset",
                      "`offset` " + to_string(offset) +
                          " needs a triangle mesh or shape input to tell inside from outside: use `offset` "
                          "centered");
  test.winding.emplace(*placed.mesh);
  const double step = 0.25 * h;
  test.side = [&winding = *test.winding, step](const Vec3& x, const Vec3& cp) {
    return side_of_surface(winding, x, cp, step);
  };
}

std::vector<WallProbe> wall_probes(const PlacedSurface& placed, const NarrowBand& band,
                                   std::span<const double> phi, double iso, double wall_mm, WallOffset offset,
                                   const SideFunction& side) {
  std::vector<WallProbe> probes;
  const std::size_t count = 256, stride = std::max<std::size_t>(1, band.size() / (4 * count));
  const double h = band.grid().h();
  const double below = 0.5 * (iso + *std::min_element(phi.begin(), phi.end()));
  // Near an open boundary the wall ends in the trim line's flat face: a probe there would cross that
  // face or the edge where it meets the wall's, not the wall (a probe on the face's plane measured 1.09
  // mm on a 2.5 mm sleeve). Probes keep half a wall and a cell behind the line.
  const double clearance = 0.5 * wall_mm / placed.mm_per_grid() + h;
  std::optional<TrimLine> trim;
  if (const TriangleMesh* open = placed.open_mesh()) trim.emplace(*open, clearance);
  for (std::size_t v = 0; v < band.size() && probes.size() < count; v += stride) {
    if (!(phi[v] < below)) continue;
    const Vec3 x = band.grid().position(band.voxels()[v]);
    const std::optional<Vec3> cp = closest_point_at(*placed.surface, x, h, ClosestPointRule::exact);
    if (!cp || (x - *cp).norm() < 0.25 * h) continue;  // the normal is only defined off the surface
    // The mirror point across the surface must share the closest point, else cp is on an open edge or
    // the surface folds within h: the line along x - cp would not cross the wall.
    const std::optional<Vec3> mirror =
        closest_point_at(*placed.surface, 2.0 * *cp - x, h, ClosestPointRule::exact);
    if (!mirror || (*mirror - *cp).norm() > 0.25 * h) continue;
    if (trim)
      if (const std::optional<double> beyond = trim->beyond(*cp); beyond && *beyond > -clearance) continue;
    Vec3 n = (x - *cp).normalized();
    if (offset != WallOffset::centered) {
      const double outside = side ? side(x, *cp) : placed.surface->distance(x);
      if (outside == 0.0) continue;
      if (outside < 0.0) n = -n;
    }
    const double centre = offset == WallOffset::centered ? 0.0 : (offset == WallOffset::outside ? 0.5 : -0.5);
    probes.push_back({placed.to_mm(*cp) + centre * wall_mm * n, n});
  }
  return probes;
}

HoleTable output_hole_table(const TriangleMesh& mesh_mm, const HoleStats& holes_mm,
                            const PlacedSurface& placed, double h, double wall_mm, double cell_mm,
                            WallOffset offset, const SideFunction& side) {
  if (holes_mm.holes.empty()) return {};
  const double mm = placed.mm_per_grid();
  std::optional<WindingNumber> winding;
  SideFunction outward = side;
  if (!outward && placed.mesh) {
    winding.emplace(*placed.mesh);
    outward = [&w = *winding, step = 0.25 * h](const Vec3& x, const Vec3& cp) {
      return side_of_surface(w, x, cp, step);
    };
  }
  const SurfaceMidWall mid_wall(*placed.surface, h, wall_mm / mm, offset, outward, mm,
                                placed.to_mm(Vec3::Zero()));
  std::vector<Vec3> centres;
  std::vector<double> reach;
  for (const BandHole& hole : holes_mm.holes) {
    centres.push_back(hole.centroid);
    reach.push_back(hole.diameter + 2.0 * cell_mm);
  }
  return measure_holes(mesh_mm, seeds_near(mid_wall, centres, reach), &mid_wall);
}

std::int64_t spots_at_open_edge(const HoleTable& table, const HoleStats& holes_mm,
                                const PlacedSurface& placed, double wall_mm) {
  if (table.uncut.empty() || !placed.mesh) return 0;
  const std::vector<Segment> boundary = boundary_segments(*placed.mesh);
  if (boundary.empty()) return 0;
  std::vector<Vec3> centres;  // in the grid's frame, the boundary's
  std::vector<double> reach;  // mm
  for (const std::size_t i : table.uncut) {
    const BandHole& hole = holes_mm.holes[i];
    centres.push_back(placed.from_mm(hole.centroid));
    reach.push_back(0.5 * hole.diameter + wall_mm);
  }
  double most = 0.0;
  for (const double r : reach) most = std::max(most, r);
  const std::vector<double> distance = segment_distances(centres, boundary, most / placed.mm_per_grid());
  std::int64_t at_edge = 0;
  for (std::size_t k = 0; k < centres.size(); ++k) at_edge += distance[k] * placed.mm_per_grid() < reach[k];
  return at_edge;
}

}  // namespace poreshell
