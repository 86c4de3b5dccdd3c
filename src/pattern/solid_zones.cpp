#include "pattern/solid_zones.hpp"

#include <fmt/core.h>

#include <tbb/parallel_for.h>

#include <Eigen/Geometry>  // cross()
#include <memory>

#include "core/cell_hash.hpp"
#include "geometry/point_tree.hpp"
#include "input/features.hpp"
#include "input/point_cloud.hpp"
#include "input/vertex_field.hpp"
#include "pattern/pattern.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace poreshell {
namespace {

// Segments registered in the cells of size `cell` that their boxes, grown by `cell`, overlap: every
// segment within `cell` of a point is listed in the point's own cell.
class SegmentBuckets {
 public:
  SegmentBuckets(std::span<const Segment> segments, double cell) : segments_(segments), cells_(cell) {
    for (std::size_t i = 0; i < segments.size(); ++i)
      cells_.add_box(segments[i][0].cwiseMin(segments[i][1]) - Vec3::Constant(cell),
                     segments[i][0].cwiseMax(segments[i][1]) + Vec3::Constant(cell),
                     static_cast<std::uint32_t>(i));
    cells_.seal();
  }

  double distance(const Vec3& p, double beyond) const { return nearest(p, beyond).first; }
  // The distance to the nearest segment and its index; (beyond, -1) where none is nearer.
  std::pair<double, std::int64_t> nearest(const Vec3& p, double beyond) const {
    std::pair<double, std::int64_t> best{beyond, -1};
    cells_.for_each_at(p, [&](std::uint32_t i) {
      const double d = segment_distance(p, segments_[i]);
      if (d < best.first) best = {d, i};
    });
    return best;
  }

 private:
  std::span<const Segment> segments_;
  CellHash cells_;
};

}  // namespace

// Per boundary segment (boundary_segments' order), the unit vector in its triangle's plane, across the
// segment, pointing onto the sheet.
std::vector<Vec3> boundary_inward(const TriangleMesh& mesh) {
  const std::vector<Edge> edges = boundary_edges(mesh);
  std::vector<Vec3> inward(edges.size(), Vec3::Zero());
  for (const Triangle& t : mesh.triangles)
    for (int k = 0; k < 3; ++k) {
      const std::int32_t a = t[static_cast<std::size_t>(k)], b = t[static_cast<std::size_t>((k + 1) % 3)];
      const Edge e{std::min(a, b), std::max(a, b)};
      const auto at = std::lower_bound(edges.begin(), edges.end(), e);
      if (at == edges.end() || *at != e) continue;
      const Vec3 &pa = mesh.vertices[static_cast<std::size_t>(a)],
                 &pb = mesh.vertices[static_cast<std::size_t>(b)];
      const Vec3& pc = mesh.vertices[static_cast<std::size_t>(t[static_cast<std::size_t>((k + 2) % 3)])];
      const Vec3 along = (pb - pa).normalized(), across = (pc - pa) - (pc - pa).dot(along) * along;
      inward[static_cast<std::size_t>(at - edges.begin())] = across.normalized();
    }
  return inward;
}

std::vector<Segment> boundary_segments(const TriangleMesh& mesh) {
  std::vector<Segment> out;
  for (const Edge& e : boundary_edges(mesh))
    out.push_back(
        {mesh.vertices[static_cast<std::size_t>(e[0])], mesh.vertices[static_cast<std::size_t>(e[1])]});
  return out;
}

std::vector<double> segment_distances(std::span<const Vec3> points, std::span<const Segment> segments,
                                      double reach) {
  const SegmentBuckets buckets(segments, reach);
  std::vector<double> out(points.size());
  tbb::parallel_for(std::size_t{0}, points.size(),
                    [&](std::size_t i) { out[i] = buckets.distance(points[i], reach); });
  return out;
}

double segment_distance(const Vec3& p, const Segment& s) {
  const Vec3 d = s[1] - s[0];
  const double len2 = d.squaredNorm();
  const double t = len2 > 0.0 ? std::clamp((p - s[0]).dot(d) / len2, 0.0, 1.0) : 0.0;
  return (p - (s[0] + t * d)).norm();
}

// Signed distance to an axis-aligned box: negative inside (minus the distance to the nearest face).
double box_distance(const Vec3& x, const SolidBox& b) {
  const Vec3 outside = (b.min - x).cwiseMax(x - b.max);
  return outside.cwiseMax(0.0).norm() + std::min(outside.maxCoeff(), 0.0);
}

std::vector<double> keep_out_gaps(const ZoneOptions& c, const SolidBox& model) {
  std::vector<double> gaps;
  for (const SolidSphere& k : c.keep_out)
    gaps.push_back(std::max(box_distance(k.center, model) - k.radius, 0.0));
  for (const SolidBox& box : c.keep_out_boxes)
    gaps.push_back((model.min - box.max).cwiseMax(box.min - model.max).cwiseMax(0.0).norm());
  return gaps;
}

std::string keep_out_name(const ZoneOptions& c, std::size_t k) {
  if (k < c.keep_out.size()) {
    const SolidSphere& s = c.keep_out[k];
    return fmt::format("`keep_out` {:g},{:g},{:g},{:g}", s.center[0], s.center[1], s.center[2], s.radius);
  }
  const SolidBox& b = c.keep_out_boxes.at(k - c.keep_out.size());
  return fmt::format("`keep_out_boxes` {:g},{:g},{:g},{:g},{:g},{:g}", b.min[0], b.min[1], b.min[2], b.max[0],
                     b.max[1], b.max[2]);
}

std::vector<double> solid_zone_weight(const NarrowBand& band, std::span<const Segment> boundary, double rim,
                                      std::span<const SolidSphere> keep_out, double ramp,
                                      std::span<const SolidBox> boxes, RampSide rim_side) {
  std::vector<double> weight(band.size(), 0.0);
  // Where the rim's weight is 0 and where 1, as depths inside its edge; an inside ramp ends at the rim's
  // full width where the rim is narrower than the ramp.
  const double rim_zero = rim_side == RampSide::outside ? -ramp : 0.0;
  const double rim_one = rim_side == RampSide::outside ? 0.0 : std::min(ramp, rim);
  const bool rims = rim > 0.0 && !boundary.empty();
  const double reach = rim - rim_zero;
  const SegmentBuckets buckets(rims ? boundary : std::span<const Segment>{}, std::max(reach, 1e-12));
  // inside_by: how far inside the zone's edge (negative outside); the weight is 0 at `zero`, 1 at `one`.
  // Written from `one` so that a ramp outside (one = 0) rounds as it did before rims could ramp inside.
  const auto ramp_weight = [](double inside_by, double zero, double one) {
    return one > zero ? std::clamp(1.0 + (inside_by - one) / (one - zero), 0.0, 1.0)
                      : (inside_by >= 0.0 ? 1.0 : 0.0);
  };
  tbb::parallel_for(std::size_t{0}, band.size(), [&](std::size_t v) {
    const Vec3 x = band.grid().position(band.voxels()[v]);
    double w = 0.0;
    if (rims) w = ramp_weight(rim - buckets.distance(x, 2.0 * reach), rim_zero, rim_one);
    for (const SolidSphere& s : keep_out)
      w = std::max(w, ramp_weight(s.radius - (x - s.center).norm(), -ramp, 0.0));
    for (const SolidBox& b : boxes) w = std::max(w, ramp_weight(-box_distance(x, b), -ramp, 0.0));
    weight[v] = w;
  });
  return weight;
}

std::vector<double> mean_concentration_field(std::span<const double> weight, double phi_bar) {
  std::vector<double> field(weight.size());
  for (std::size_t v = 0; v < weight.size(); ++v) field[v] = phi_bar + (-1.0 - phi_bar) * weight[v];
  return field;
}

std::vector<double> solid_zones(const ZoneOptions& c, const PlacedSurface& placed, const NarrowBand& band,
                                double epsilon, const std::function<double(const Vec3&)>& mask,
                                const FeatureZones& features) {
  const bool creases = !features.creases.empty() && features.crease_width > 0.0;
  if (c.rim <= 0.0 && c.keep_out.empty() && c.keep_out_boxes.empty() && !mask && !features.thin && !creases)
    return {};
  const double grid_per_mm = 1.0 / placed.mm_per_grid();
  std::vector<SolidSphere> spheres;
  for (const SolidSphere& k : c.keep_out)
    spheres.push_back({placed.from_mm(k.center), k.radius * grid_per_mm});
  std::vector<SolidBox> boxes;
  for (const SolidBox& k : c.keep_out_boxes)
    boxes.push_back(SolidBox::spanned(placed.from_mm(k.min), placed.from_mm(k.max)));
  const std::vector<Segment> boundary =
      placed.mesh ? boundary_segments(*placed.mesh) : std::vector<Segment>{};
  // The ramp lets the pattern meet the zone over about one interface width.
  std::vector<double> weight =
      solid_zone_weight(band, boundary, c.rim * grid_per_mm, spheres, 2.0 * epsilon, boxes, RampSide::inside);
  if (creases) {
    const std::vector<double> edge = solid_zone_weight(band, features.creases, features.crease_width, {},
                                                       2.0 * epsilon, {}, RampSide::outside);
    for (std::size_t v = 0; v < band.size(); ++v) weight[v] = std::max(weight[v], edge[v]);
  }
  // Masks and thin marks are 0/1 per vertex, interpolated: solid above 0.75, free below 0.25.
  const auto blend = [](double m) { return std::clamp(2.0 * (m - 0.25), 0.0, 1.0); };
  if (mask || features.thin)
    tbb::parallel_for(std::size_t{0}, band.size(), [&](std::size_t v) {
      if (mask)
        weight[v] = std::max(weight[v], blend(mask(placed.to_mm(band.grid().position(band.voxels()[v])))));
      // Asked at the voxel's closest point, where the mark belongs: a query on the surface prunes the
      // search at once (the thin zones took 0.09 s of the bunny's 1.6 s preview asked at the voxel).
      if (features.thin) weight[v] = std::max(weight[v], blend(features.thin(band.closest_point(v))));
    });
  return weight;
}

FeatureZones feature_zones(const ZoneOptions& c, const PlacedSurface& placed, double hole_diameter_mm) {
  FeatureZones zones;
  if (!(hole_diameter_mm > 0.0) || (c.thin_feature_ratio <= 0.0 && c.crease_angle <= 0.0)) return zones;
  const double hole = hole_diameter_mm / placed.mm_per_grid();
  FeatureOptions o;
  o.thin_below = c.thin_feature_ratio * hole;
  o.margin = 0.5 * hole;  // a hole centred nearer would reach into the thin part
  o.crease_degrees = c.crease_angle;
  o.min_crease_length = hole;
  // A point cloud (the direct route's splats): thin parts from its points, each voxel taking its nearest
  // point's mark; it has no edges to find creases on.
  if (const auto* splats = dynamic_cast<const SplatSurface*>(placed.surface.get())) {
    // One tree over the points: the test's neighbours, then each voxel's nearest point.
    auto tree = std::make_shared<const PointTree>(
        std::vector<Vec3>(splats->points().begin(), splats->points().end()));
    std::vector<double> thin =
        thin_points(splats->points(), splats->normals(), splats->radii(), *tree, *splats, o);
    zones.thin_vertices = static_cast<std::int64_t>(std::count(thin.begin(), thin.end(), 1.0));
    if (zones.thin_vertices > 0)
      zones.thin = [tree, marks = std::move(thin)](const Vec3& x) { return marks[tree->nearest(x).first]; };
    return zones;
  }
  if (!placed.mesh) return zones;
  SurfaceFeatures f = find_surface_features(*placed.mesh, *placed.surface, o);
  zones.thin_vertices = f.thin_vertices;
  zones.crease_edges = f.crease_edges;
  if (f.thin_vertices > 0) {
    // Only the triangles with a marked vertex: the field is 0 on all others, and the solid zones ask at
    // points on the surface (the voxels' closest points, within rounding of it), so a point no marked
    // triangle reaches is 0 without finding its triangle (the bunny's thin zones: 8% of its preview).
    std::vector<Triangle> marked;
    for (const Triangle& t : placed.mesh->triangles)
      if (std::any_of(t.begin(), t.end(),
                      [&](std::int32_t v) { return f.thin[static_cast<std::size_t>(v)] > 0.0; }))
        marked.push_back(t);
    auto field = std::make_shared<const VertexScalarField>(placed.mesh->vertices, std::move(f.thin),
                                                           std::move(marked), "thin");
    constexpr double kOnSurface = 1e-6;  // grid units: h is 1e-3 to 1e-2, float closest points 1e-9 off
    zones.thin = [field](const Vec3& x) { return field->at_or(x, kOnSurface, 0.0); };
  }
  zones.creases.assign(f.creases.begin(), f.creases.end());
  zones.crease_width = 0.5 * hole;
  return zones;
}

ZoneAreas zone_areas(const ZoneOptions& c, const PlacedSurface& placed, const NarrowBand& band,
                     const FeatureZones& features, const std::function<double(const Vec3&)>& mask) {
  const double mm = placed.mm_per_grid(), grid_per_mm = 1.0 / mm;
  std::vector<Vec3> foot(band.size());
  std::vector<double> area(band.size());
  std::vector<char> thin(band.size(), 0), masked(band.size(), 0);
  tbb::parallel_for(std::size_t{0}, band.size(), [&](std::size_t v) {
    area[v] = band.surface_area(v) * mm * mm;
    foot[v] = band.closest_point(v);
    if (!(area[v] > 0.0)) return;  // no share of the surface: no rule to ask
    thin[v] = features.thin && features.thin(foot[v]) >= 0.5;
    masked[v] = mask && mask(placed.to_mm(foot[v])) >= 0.5;
  });
  const auto near = [&](std::span<const Segment> segments, double width) {
    std::vector<char> in(foot.size(), 0);
    if (segments.empty() || !(width > 0.0)) return in;
    const std::vector<double> d = segment_distances(foot, segments, width);
    for (std::size_t i = 0; i < d.size(); ++i) in[i] = d[i] < width ? 1 : 0;
    return in;
  };
  const std::vector<Segment> boundary =
      placed.mesh ? boundary_segments(*placed.mesh) : std::vector<Segment>{};
  const std::vector<char> creases = near(features.creases, features.crease_width);
  // Near an open edge each voxel's share of the surface is a strip one voxel wide, [u - h/2, u + h/2] in
  // u, the distance onto the sheet across the edge: its foot's distance to the edge, or for a voxel whose
  // foot is on the edge (within a thousandth of a voxel: feet are float offsets) its own offset across
  // the edge, negative past it. Only what of the strip lies on the sheet counts, and for the rim what lies
  // within the rim. Counting whole voxels, a 4 mm rim on a sleeve came out 3 % over (a row of voxels
  // past each edge) or 17 % under (without the rows on the edges), as the grid's rows fell (issue 51).
  const double rim = c.rim * grid_per_mm, h = band.grid().h();
  std::vector<double> on_sheet(foot.size(), 1.0), in_rim(foot.size(), 0.0);
  if (!boundary.empty()) {
    const SegmentBuckets buckets(boundary, rim + h);
    const std::vector<Vec3> inward = boundary_inward(*placed.mesh);
    tbb::parallel_for(std::size_t{0}, foot.size(), [&](std::size_t v) {
      const auto [d, i] = buckets.nearest(foot[v], rim + h);
      const double u =
          i >= 0 && d < 1e-3 * h
              ? (band.grid().position(band.voxels()[v]) - foot[v]).dot(inward[static_cast<std::size_t>(i)])
              : d;
      on_sheet[v] = std::clamp(u / h + 0.5, 0.0, 1.0);
      in_rim[v] = std::clamp((std::min(u + 0.5 * h, rim) - std::max(u - 0.5 * h, 0.0)) / h, 0.0, 1.0);
    });
  }
  ZoneAreas areas;
  const Box bounds = placed.surface->bounds();
  const std::vector<double> gaps =
      keep_out_gaps(c, SolidBox::spanned(placed.to_mm(bounds.min), placed.to_mm(bounds.max)));
  areas.each_keep_out.resize(gaps.size());
  for (std::size_t k = 0; k < gaps.size(); ++k) areas.each_keep_out[k].outside_bounds = gaps[k] > 0.0;
  for (std::size_t v = 0; v < foot.size(); ++v) {
    const double share = area[v];  // the whole strip's
    area[v] *= on_sheet[v];
    if (!(area[v] > 0.0)) continue;
    const Vec3 x = placed.to_mm(foot[v]);
    bool kept = masked[v];
    std::size_t k = 0;
    const auto keep_out = [&](double outside) {  // x's distance outside keep-out k, negative inside
      ZoneAreas::KeepOutReach& reach = areas.each_keep_out[k++];
      reach.gap_mm = std::min(reach.gap_mm, std::max(outside, 0.0));
      reach.area += outside < 0.0 ? area[v] : 0.0;
      kept = kept || outside < 0.0;
    };
    for (const SolidSphere& sphere : c.keep_out) keep_out((x - sphere.center).norm() - sphere.radius);
    for (const SolidBox& box : c.keep_out_boxes) keep_out(box_distance(x, box));
    areas.surface += area[v];
    areas.thin += thin[v] ? area[v] : 0.0;
    areas.creases += creases[v] ? area[v] : 0.0;
    areas.rims += in_rim[v] * share;
    areas.keep_outs += kept ? area[v] : 0.0;
    areas.solid += thin[v] || creases[v] || kept ? area[v] : in_rim[v] * share;
  }
  return areas;
}

std::int64_t close_spots_in_rim(const NarrowBand& band, std::span<double> phi, double level,
                                std::span<const Segment> boundary, double rim) {
  if (boundary.empty() || !(rim > 0.0)) return 0;
  const std::vector<std::int32_t> label = label_spots(band, phi, level);
  std::vector<double> area;
  std::vector<Vec3> centre;
  for (std::size_t v = 0; v < label.size(); ++v) {
    if (label[v] < 0) continue;
    const auto l = static_cast<std::size_t>(label[v]);
    if (l >= area.size()) {
      area.resize(l + 1, 0.0);
      centre.resize(l + 1, Vec3::Zero());
    }
    const double a = band.surface_area(v);
    area[l] += a;
    centre[l] += a * band.closest_point(v);
  }
  double widest = 0.0;
  std::vector<double> radius(area.size());
  for (std::size_t l = 0; l < area.size(); ++l) {
    if (area[l] > 0.0) centre[l] /= area[l];
    radius[l] = std::sqrt(area[l] / std::numbers::pi);
    widest = std::max(widest, radius[l]);
  }
  const std::vector<double> distance = segment_distances(centre, boundary, rim + widest);
  std::vector<char> close(area.size(), 0);
  std::int64_t closed = 0;
  for (std::size_t l = 0; l < area.size(); ++l)
    if (area[l] > 0.0 && distance[l] - radius[l] < rim) {
      close[l] = 1;
      ++closed;
    }
  for (std::size_t v = 0; v < label.size(); ++v)
    if (label[v] >= 0 && close[static_cast<std::size_t>(label[v])]) phi[v] = -1.0;
  return closed;
}

}  // namespace poreshell
