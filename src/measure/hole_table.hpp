#pragma once
// The hole table: every pore of a written solid measured on its triangles, not on the band's voxels.
// Each hole is cut through the wall's middle; the cut's closed loop around the hole, seen along the
// surface normal, gives its equivalent diameter sqrt(4 A / pi), circularity 4 pi A / P^2 (A area,
// P perimeter) and axis ratio (of its area's principal second moments, b / a for an ellipse), and the
// loop's centroid its centre. What a printed part's pores are, hole by hole.

#include <cstddef>
#include <optional>
#include <span>
#include <vector>

#include "geometry/mesh.hpp"
#include "geometry/surface.hpp"
#include "shell/shell.hpp"

namespace poreshell {

// Where to cut one hole.
struct HoleSeed {
  Vec3 point = Vec3::Zero();    // near the hole's axis, at the wall's middle
  Vec3 normal = Vec3::UnitZ();  // unit: the surface normal, outward where the surface has a side
  double reach = 0.0;           // the hole's loop must lie within this distance of `point`
};

struct HoleRecord {
  Vec3 centre = Vec3::Zero();  // the cut loop's centroid, at the wall's middle
  Vec3 normal = Vec3::UnitZ();
  double diameter = 0.0;     // sqrt(4 A / pi) of the cut, seen along the normal
  double circularity = 0.0;  // 4 pi A / P^2: 1 for a circle, pi / 4 for a square
  // sqrt of the least over the greatest principal second moment of the area: b / a for an ellipse (whose
  // circularity says little: 0.97 at b / a = 0.75, 0.91 at 0.6), 1 for a circle or a square.
  double axis_ratio = 0.0;
  double nearest = 0.0;  // distance to the nearest other centre; 0 for a lone hole
};

struct HoleTable {
  std::vector<HoleRecord> holes;  // in the order of the seeds they came from
  // Seeds with no closed loop around them (a notch at an open edge, a spot that did not cut through),
  // or whose loop another seed measured first.
  std::size_t dropped = 0;
  std::vector<std::size_t> uncut;  // the first kind: indices into the seeds, ascending
};

// The middle of the wall, in the mesh's frame. Called from several threads at once.
class MidWall {
 public:
  virtual ~MidWall() = default;
  // A seed near x (reach 0): the nearest point of the wall's middle and the surface normal there.
  virtual std::optional<HoleSeed> seed(const Vec3& x) const = 0;
  // The nearest point of the wall's middle to x, the wall's offset taken along `normal`.
  virtual std::optional<Vec3> point(const Vec3& x, const Vec3& normal) const = 0;
  // Signed distance of x from the wall's middle, positive on the outside (the side `normal` points to
  // where the surface has no side).
  virtual std::optional<double> height(const Vec3& x, const Vec3& normal) const = 0;
};

// Cuts the closed, outward-oriented mesh at each seed and measures the smallest closed loop around the
// seed that bounds an opening (solid outside it), seen along the hole's axis. With `mid_wall` the cut
// follows the wall's middle, sampled on rings about the seed out to its reach, so that it stays inside
// a curved wall, and the axis is the normal of the middle fitted over half the reach; where that cut
// finds no loop (the wall's middle turning too fast for the samples), the loop where the hole's wall
// crosses mid_wall's heights' zero is traced across the mesh. Without `mid_wall` the cut is the plane
// through the seed normal to its normal. A loop whose centroid lies well off its seed (more than a
// tenth of its radius) is cut again from mid_wall->seed(centroid). Seeds of reach 0 are dropped.
// Deterministic, whatever the thread count.
HoleTable measure_holes(const TriangleMesh& mesh, std::span<const HoleSeed> seeds,
                        const MidWall* mid_wall = nullptr);

// mid_wall.seed at each approximate centre, in parallel, with the given reach (0 where it gives none).
std::vector<HoleSeed> seeds_near(const MidWall& mid_wall, std::span<const Vec3> centres,
                                 std::span<const double> reach);

// The wall's middle of a surface (shell.hpp's slab: centred on it, or half the thickness outside or
// inside it), in a frame x_mesh = scale x_surface + shift. A seed's normal is a plane fitted to the
// closest points of 14 points about its closest point at distance h, turned outward by `side` (empty:
// the sign of the surface's distance; where that has no sign, a fixed choice). Heights are distances
// to the surface signed by `side` (empty: by `normal`), less the offset.
class SurfaceMidWall final : public MidWall {
 public:
  SurfaceMidWall(const Surface& surface, double h, double thickness, WallOffset offset, SideFunction side,
                 double scale = 1.0, const Vec3& shift = Vec3::Zero());
  std::optional<HoleSeed> seed(const Vec3& x) const override;
  std::optional<Vec3> point(const Vec3& x, const Vec3& normal) const override;
  std::optional<double> height(const Vec3& x, const Vec3& normal) const override;

 private:
  const Surface& surface_;
  double h_, shift_along_normal_;  // surface frame
  SideFunction side_;
  double scale_;
  Vec3 shift_;
};

}  // namespace poreshell
