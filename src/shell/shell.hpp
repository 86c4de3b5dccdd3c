#pragma once
// The printable shell with a wall thickness of its own (issue 4, item 2): the solid is
//   { x : the signed distance d(x) lies in the wall slab }  and  { phi_ext(x) < iso },
// where phi_ext is the band's pattern extended constant along the surface normal (phi at cp(x)), so
// pores go straight through the wall. The slab is |d| <= t/2 (centered), -t <= d <= 0 (inside) or
// 0 <= d <= t (outside). The solid is the set F < 0 of
//   F(x) = max(|d(x) - c| - t/2,  s (phi_ext(x) - iso)),   c = 0, -t/2 or t/2,
// with s a length, sampled on a sparse set of grid points around the surface and meshed by marching
// tetrahedra (closed, manifold). The pipeline takes s = 4 sqrt(2) eps, four times the interface's unit
// slope: the pattern term must be well below the wall term inside the solid, else the crease of the max
// falls between samples at the faces and thins the wall where bridges are narrow (8 mm holes at 10 mm:
// a 2 mm wall measured 1.83 mm with s = sqrt(2) eps, 2.00 mm with 4 times that).
// On an open surface the solid is also cut at the boundary: F = max(F, s), s the signed distance beyond
// the trim line along the surface's outward tangent (trim_line.hpp), so the wall ends with a flat face
// at the boundary for every offset instead of a rounded cap that wraps around the edge.
// Memory grows with the surface area times the wall thickness, never with the bounding box.

#include <functional>
#include <span>
#include <string>
#include <vector>

#include "band/band.hpp"
#include "core/grid.hpp"
#include "core/run_monitor.hpp"
#include "geometry/mesh.hpp"
#include "geometry/surface.hpp"
#include "poreshell/options.hpp"
#include "shell/parts.hpp"

namespace poreshell {

std::string to_string(WallOffset offset);

// Side of the surface a point lies on: > 0 outside (where the normals point), < 0 inside.
// Arguments: the point and its closest surface point.
using SideFunction = std::function<double(const Vec3&, const Vec3&)>;

struct ShellOptions {
  double thickness = 0.0;  // t, in the surface's length unit
  WallOffset offset = WallOffset::centered;
  double pattern_length = 0.0;  // s; must be > 0
  // Spacing of the shell's grid. 0: the band's h, refined so that the wall spans at least
  // kMinCellsAcrossWall cells.
  double spacing = 0.0;
  // Needed for inside/outside when the surface's distance is unsigned; empty: the sign of
  // Surface::distance is used.
  SideFunction side;
  // A mesh input's triangles, in the surface's frame, when it has an open boundary: the wall then ends
  // there with a flat face across it (trim_line.hpp). Null: no boundary, no trim.
  const TriangleMesh* open_mesh = nullptr;
  StageProgress progress{};  // the sampling's share of its stage (checked, reported)
};

inline constexpr double kMinCellsAcrossWall = 3.0;

struct ShellSamples {
  Grid grid{Vec3::Zero(), 1.0, {3, 3, 3}};
  std::vector<Coord> points;  // grid points within t/2 + sqrt(3) cells of the wall's middle, by key
  std::vector<double> wall;   // |d - c| - t/2: negative inside the wall slab (and behind the trim line)
  // With a trim line: the wall's two parts, the slab |d - c| - t/2 (past the line, d the distance to the
  // surface's tangent plane at the boundary) and the distance beyond the trim line (very negative far
  // from it); wall is their max. Empty without one.
  std::vector<double> slab, trim;
  std::vector<double> pattern;  // phi_ext
  double pattern_length = 0.0;
  std::int64_t incomplete_stencils = 0;  // closest points with band corners missing (renormalised)
};

// Samples the wall and the extended pattern. `phi` holds the band's values (band order).
ShellSamples sample_shell(const Surface& surface, const NarrowBand& band, std::span<const double> phi,
                          const ShellOptions& options);

// The solid { wall < 0 and phi_ext < iso }, closed and outward oriented.
// Vertices on the creases where the pores meet the wall's faces (isosurface.hpp), unless `sharp_creases`
// is false: a reduction to a triangle budget then starts from the chamfered surface, as the creases'
// vertices hold it back (the bunny, 6 mm holes at 10 mm, 0.05 mm: 200,000 triangles no longer reachable,
// 205,646 the fewest; at 210,000 its cost 0.39-0.43 -> 0.50-0.52 of the unreduced run).
TriangleMesh shell_mesh(const ShellSamples& samples, double iso, const StageProgress& progress = {},
                        bool sharp_creases = true);

// The wall without pores: the reference for counting pores by the Euler characteristic.
TriangleMesh unperforated_shell_mesh(const ShellSamples& samples);
// Its Euler characteristic, without making it.
std::int64_t unperforated_shell_euler(const ShellSamples& samples, const StageProgress& progress = {});
// The samples inside the wall without pores, by key: whether a point is, once the samples are gone.
struct SolidWallPoints {
  Grid grid{Vec3::Zero(), 1.0, {3, 3, 3}};
  std::vector<std::int64_t> keys;  // ascending
  // Whether the grid point nearest p is one of them.
  bool contains(const Vec3& p) const;
};
SolidWallPoints solid_wall_points(const ShellSamples& samples);
// Of the voids keep_main_parts removed, those the wall without pores has as well (where a part is a
// little thicker than the wall, the slab leaves a pocket farther than t/2 from the surface): counted in
// parts.removed_wall_voids. Returns the sum of their Euler characteristics, which the wall without
// pores has too, so that pores from the Euler characteristic do not count them as missing pores (the
// bunny at 8 mm with the default wall: 217 against 183 holes, 34 such voids). A void with its sample
// outside the wall without pores is one: the solid with pores is a subset of it. `to_grid` maps the
// mesh's coordinates to the samples'.
std::int64_t wall_voids_euler(PartsSummary& parts, const SolidWallPoints& wall,
                              const std::function<Vec3(const Vec3&)>& to_grid);

// phi at an arbitrary point of the band's grid by trilinear interpolation of band values (the same rule
// as the ghosts' stencils). Corners outside the band are left out and the weights renormalised;
// `complete` reports whether all 8 were present. No corner at all gives -1 (solid: keep the wall).
double interpolate_band(const NarrowBand& band, std::span<const double> phi, const Vec3& p, bool* complete);

}  // namespace poreshell
