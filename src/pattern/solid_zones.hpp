#pragma once
// Where the wall must stay solid: a rim along the open boundary of a sheet (a cast's edge) and
// keep-out spheres and boxes. They act inside the model, as a local mean concentration phi_bar(x) raised to
// the solid phase -1, so the pattern arranges itself around them instead of being cut afterwards.

#include <array>
#include <functional>
#include <limits>
#include <span>
#include <string>
#include <vector>

#include "band/band.hpp"
#include "geometry/mesh.hpp"
#include "input/placement.hpp"

namespace poreshell {

using Segment = std::array<Vec3, 2>;

struct SolidSphere {
  Vec3 center = Vec3::Zero();
  double radius = 0.0;
};

struct SolidBox {
  Vec3 min = Vec3::Zero(), max = Vec3::Zero();  // axis-aligned corners

  // From any two opposite corners (a keep-out box is given by two, in either order).
  static SolidBox spanned(const Vec3& a, const Vec3& b) { return {a.cwiseMin(b), a.cwiseMax(b)}; }
};

// Distance from a point to a segment, and the signed distance to a box (negative inside).
double segment_distance(const Vec3& p, const Segment& s);
double box_distance(const Vec3& x, const SolidBox& b);

// What the solid zones are asked for: the request's share for this room (zone_options() in
// pipeline/stage_options.hpp resolves it once). Lengths in mm, in the input's frame.
struct ZoneOptions {
  double rim = 0.0;  // along the open boundary; 0: none
  std::vector<SolidSphere> keep_out;
  std::vector<SolidBox> keep_out_boxes;
  double thin_feature_ratio = 0.0;  // times the hole diameter; 0: off
  double crease_angle = 0.0;        // degrees; 0: off
  bool any_keep_out() const { return !keep_out.empty() || !keep_out_boxes.empty(); }
};

// How far each keep-out (the spheres, then the boxes) lies from the box `model` (mm; 0 where it reaches
// into it). One that misses the model's bounds keeps nothing: the estimate names it before the run, so
// the report need not say it again.
std::vector<double> keep_out_gaps(const ZoneOptions& zones, const SolidBox& model);
// Keep-out k (same order) as the request gives it, for messages: "`keep_out` x,y,z,r".
std::string keep_out_name(const ZoneOptions& zones, std::size_t k);

// Edges with exactly one incident triangle (the open boundary), as segments.
std::vector<Segment> boundary_segments(const TriangleMesh& mesh);

// Each point's distance to the nearest segment, or `reach` where none is nearer (reach > 0).
std::vector<double> segment_distances(std::span<const Vec3> points, std::span<const Segment> segments,
                                      double reach);

// Which side of a rim's edge its weight falls from 1 to 0. Inside, the pattern may begin where the
// asked rim ends: with the ramp outside, the nearest holes kept 2.7-3.9 mm more than the asked rim from
// a sleeve's edge (8 mm holes at 12 mm, rims of 1-10 mm), with it inside 0.5-1.9 mm (docs/printing.md,
// "The rim asked is the rim made"); the layout's own clearance of open edges still keeps discs off a
// narrow one. A crease's zone ramps outside: its width is already the margin a hole keeps from the
// crease. Keep-out spheres and boxes always ramp outside: ramping inside or across their edge, holes
// reached into them (small spheres, a sphere beside a box), which have no such clearance.
enum class RampSide { inside, outside };

// Per band voxel, the weight of the zones within `rim` of a boundary segment (ramping on `rim_side` of
// its edge) and inside keep-out spheres and boxes (1 inside, 0 beyond a further `ramp`); linear across
// the ramps; all lengths in the band's grid units.
std::vector<double> solid_zone_weight(const NarrowBand& band, std::span<const Segment> boundary, double rim,
                                      std::span<const SolidSphere> keep_out, double ramp,
                                      std::span<const SolidBox> boxes = {},
                                      RampSide rim_side = RampSide::inside);

// Makes solid every spot {phi > level} that, as a disc of its area about the mean of its closest points,
// would come nearer than `rim` to a boundary segment (grid units): the rim asked is the rim made, also
// where a scan's open boundary turns (issue 51: the bunny's base at 8 / 14 mm left 2.72 mm of a 3 mm rim).
// The output's rim is measured the same way on the mesh's holes (shell/zone_check.hpp), whose diameters
// are under the band's. Returns how many it closed.
std::int64_t close_spots_in_rim(const NarrowBand& band, std::span<double> phi, double level,
                                std::span<const Segment> boundary, double rim);

// phi_bar(x) = phi_bar + (-1 - phi_bar) w(x): the nonlocal term's target, solid where w = 1.
std::vector<double> mean_concentration_field(std::span<const double> weight, double phi_bar);

// Per band voxel, how solid the wall must stay (0 free, 1 solid) from the options (mm, input frame): rims
// along the mesh's open boundary, keep-out spheres and boxes, and a keep-out mask (a 0/1 vertex field,
// evaluated by `mask` at points in mm, blended over 0.25-0.75). Empty where nothing is kept out.
// Thin parts and creases of the input (input/features.hpp) in grid units: `thin` evaluates the thin
// marks at a point on the surface (0 off the marked triangles), creases are kept `crease_width` clear.
struct FeatureZones {
  std::function<double(const Vec3&)> thin;
  std::vector<Segment> creases;
  double crease_width = 0.0;
  std::int64_t thin_vertices = 0, crease_edges = 0;  // what was found, for the report
};
std::vector<double> solid_zones(const ZoneOptions& options, const PlacedSurface& placed,
                                const NarrowBand& band, double epsilon,
                                const std::function<double(const Vec3&)>& mask,
                                const FeatureZones& features = {});

// The surface's area each rule keeps solid (mm^2, from the band's voxels: each carries its share of the
// surface at its closest point, which counts for a rule where it is in the rule's zone, so overlaps count
// in each), and in all: what the report gives per rule, so that a designer sees which rule took the
// porosity (issue 51). Every input: meshes, point clouds and shapes.
struct ZoneAreas {
  double surface = 0.0, thin = 0.0, creases = 0.0, rims = 0.0, keep_outs = 0.0, solid = 0.0;
  // Per keep-out (the spheres, then the boxes): the surface it keeps, how far the surface lies outside
  // it (0 where it reaches the surface), and whether it misses the model's bounding box
  // (keep_out_gaps), so that one that keeps nothing is said once (issue 51).
  struct KeepOutReach {
    double area = 0.0, gap_mm = std::numeric_limits<double>::infinity();
    bool outside_bounds = false;
  };
  std::vector<KeepOutReach> each_keep_out;
};
ZoneAreas zone_areas(const ZoneOptions& options, const PlacedSurface& placed, const NarrowBand& band,
                     const FeatureZones& features, const std::function<double(const Vec3&)>& mask);

// The thin parts and creases of a mesh input for holes of `hole_diameter_mm` (the options' thresholds);
// none for shapes and point clouds.
FeatureZones feature_zones(const ZoneOptions& options, const PlacedSurface& placed, double hole_diameter_mm);

}  // namespace poreshell
