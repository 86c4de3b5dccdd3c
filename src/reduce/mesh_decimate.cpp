#include "reduce/mesh_decimate.hpp"

// Edge collapses (edge_collapse.hpp) make the reduction; the result is then checked with
// analyze_topology(), searches across the original's edges (OriginalSurface::distance2_from()) and,
// for the original vertices, their distance to the triangle each was last distributed over, with a
// MeshSurface over the reduced mesh for any whose distance that does not settle. On the bunny's shell
// (1.5 M -> 200 k triangles, 0.05 mm) that settles them all: 0.02 s instead of 0.26-0.33 s with a
// tree over the reduced mesh and a query per vertex.
//
// The distance bound needs both directions. The original vertices within the tolerance of the
// reduced surface give one. Not the other: on poreshell's shells, triangles then bridge the concave
// rims of pores and fold over triangles that the original vertices find close instead, up to 7 times
// the tolerance off the original surface. So the centroid of every new triangle and the midpoint of
// every new edge are checked against the original surface as well; these are the points the result
// is measured at.

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>

#include "core/error.hpp"
#include "geometry/mesh_surface.hpp"
#include "geometry/printability.hpp"
#include "reduce/collapse_bounds.hpp"
#include "reduce/edge_collapse.hpp"
#include "reduce/placed_collapse.hpp"

namespace poreshell {
namespace {

// The result meets the bound by construction but for the removed vertices' distances, measured to
// the triangles they were last distributed over only, and for the points between those the checked
// collapses looked at. Should the measured or the sampled distance exceed the bound all the same, the
// reduction is redone from the original with the tolerance scaled down by the overshoot, and the last
// time by the fans' bounds alone (DistanceRule::kBoundOnly), which hold everywhere.
constexpr int kAttempts = 4;
// The share of the bound the placed collapses (placed_collapse.hpp) measure their points against: between
// its points a triangle strays further than at them (a quadratic's values at a triangle's corners and
// midpoints let it reach 1.7 times their largest in between), and an original triangle spans folds of
// the reduced surface. At 0.6 the sampled check found 0.82-0.84 of the bound on the sphere r 50 mm (6 mm
// holes at 10 mm) and the demo bunny (8 mm at 14 mm); at 0.675 it found 1.0-1.16, and a second attempt
// costs as much as the first.
constexpr double kPlacedShare = 0.6;

void validate(const DecimateOptions& options) {
  if (options.max_triangles < 4)
    throw InputError("the triangle limit must be at least 4, the fewest a closed mesh has; got " +
                     std::to_string(options.max_triangles));
  if (!std::isfinite(options.max_distance) || options.max_distance <= 0.0)
    throw InputError(
        "the distance bound for reducing triangles must be a positive number in the mesh's units; got " +
        std::to_string(options.max_distance));
}

// Where the collapsed mesh's vertices are: the original's, unless the collapses moved them.
const std::vector<Vec3>& positions(const TriangleMesh& original, const CollapsedMesh& collapsed) {
  return collapsed.positions.empty() ? original.vertices : collapsed.positions;
}

// The triangles kept, in their original order, over the vertices they use, in their original order.
TriangleMesh compact(const TriangleMesh& original, const CollapsedMesh& collapsed) {
  const std::vector<std::array<std::int32_t, 3>>& triangles = collapsed.triangles;
  const std::vector<Vec3>& at = positions(original, collapsed);
  std::vector<std::int32_t> index(original.vertices.size(), -1);
  for (const auto& t : triangles)
    for (const std::int32_t v : t) index[static_cast<std::size_t>(v)] = 0;
  TriangleMesh reduced;
  for (std::size_t v = 0; v < index.size(); ++v)
    if (index[v] == 0) {
      index[v] = static_cast<std::int32_t>(reduced.vertices.size());
      reduced.vertices.push_back(at[v]);
    }
  reduced.triangles.reserve(triangles.size());
  for (const auto& t : triangles)
    reduced.triangles.push_back({index[static_cast<std::size_t>(t[0])], index[static_cast<std::size_t>(t[1])],
                                 index[static_cast<std::size_t>(t[2])]});
  return reduced;
}

// The largest of grow(i, d) over i < count and `start`, where grow returns the larger of d (the largest
// so far) and the value at i, and may stop a search once that is within d. A maximum is exact in any
// order: the same on any number of threads.
template <class Grow>
double largest_over(std::size_t count, double start, const Grow& grow) {
  return tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(0, count), start,
      [&](const tbb::blocked_range<std::size_t>& r, double d) {
        for (std::size_t i = r.begin(); i != r.end(); ++i) d = grow(i, d);
        return d;
      },
      [](double a, double b) { return std::max(a, b); });
}

// A removed vertex's distance to the triangle it was last distributed over, which bounds its distance
// to the reduced surface; 0 for the vertices the reduced triangles keep.
double carrier_distance(const TriangleMesh& original, const TriangleMesh& reduced,
                        const std::vector<std::int32_t>& carrier, std::size_t v) {
  if (carrier[v] < 0) return 0.0;  // a vertex of the reduced triangles, or of no triangle at all
  const auto& t = reduced.triangles[static_cast<std::size_t>(carrier[v])];
  const Vec3 &a = reduced.vertices[t[0]], &b = reduced.vertices[t[1]], &c = reduced.vertices[t[2]];
  return (closest_point_on_triangle(original.vertices[v], a, b, c, classify_triangle(a, b, c)) -
          original.vertices[v])
      .norm();
}

// At least the largest distance from the original's vertices to the reduced surface where it exceeds
// `floor`; else a value no larger than floor: the vertices whose carrier distance exceeds floor are
// searched for, over a tree of the reduced mesh.
double searched_vertex_distance(const TriangleMesh& original, const TriangleMesh& reduced,
                                const std::vector<std::int32_t>& carrier, double floor) {
  const MeshSurface surface(reduced);
  return largest_over(carrier.size(), 0.0, [&](std::size_t v, double d) {
    return carrier_distance(original, reduced, carrier, v) > floor
               ? std::max(d, surface.distance(original.vertices[v]))
               : d;
  });
}

// From the reduced surface's centroids and edge midpoints, where a flat triangle strays furthest from
// a curved surface short of a dense sampling, to the original surface (searched from the original
// vertices of the same names), where that exceeds `at_least`; else at_least. `kept` are the reduced
// triangles over the vertices `at`.
double distance_to_original(const OriginalSurface& original, const std::vector<Vec3>& at,
                            const std::vector<std::array<std::int32_t, 3>>& kept, double at_least) {
  const double d2 = largest_over(kept.size(), at_least * at_least, [&](std::size_t f, double d) {  // squared
    const auto& t = kept[f];
    const Vec3 &a = at[t[0]], &b = at[t[1]], &c = at[t[2]];
    // A search may stop once it is within the largest so far: the maximum stays exact.
    d = std::max(d, original.distance2_from((a + b + c) / 3.0, {t[0], t[1], t[2]}, d));
    for (int i = 0; i < 3; ++i)
      if (const std::int32_t u = t[i], w = t[(i + 1) % 3]; u < w)  // each edge of a closed mesh once
        d = std::max(d, original.distance2_from(0.5 * (at[u] + at[w]), {u, w}, d));
    return d;
  });
  return std::sqrt(d2);
}

// The reduced surface's distance from the original, both ways, as far as the centroids, midpoints and
// the original's vertices measure it (see the top of this file). Where every vertex's carrier distance
// is within `limit`, the largest stands for the vertices' distance (a search could only lower it), and
// the centroids' and midpoints' searches start from it: each stops at the first triangle within it,
// where from 0 the first searches of each task went on to the nearest (the bunny's shell: 0.20 s ->
// 0.16-0.17 s). Else the vertices over the centroids' and midpoints' distance are searched for: on the
// pipeline's shell of the bunny at 6 / 10 mm some lie between that (0.0499998 mm) and the limit (0.05),
// and a tree built for them cost 0.12 s only to find the same distance.
double reduced_distance(const OriginalSurface& surface, const TriangleMesh& original,
                        const TriangleMesh& reduced, const CollapsedMesh& collapsed, double limit) {
  const double carried = largest_over(collapsed.carrier.size(), 0.0, [&](std::size_t v, double d) {
    return std::max(d, carrier_distance(original, reduced, collapsed.carrier, v));
  });
  const std::vector<Vec3>& at = positions(original, collapsed);
  if (carried <= limit) return distance_to_original(surface, at, collapsed.triangles, carried);
  const double to_original = distance_to_original(surface, at, collapsed.triangles, 0.0);
  return std::max(to_original, searched_vertex_distance(original, reduced, collapsed.carrier, to_original));
}

// The sampled check (deviation_check.hpp) at points the collapses never chose: from points on the
// reduced surface to the original's sheet through their triangle's corners (at least the distance to
// the whole surface, and no tree over the original to build: on the bunny's 2.1 M triangles that tree
// and check_deviation()'s queries took 3.5 s of a 15 s reduction), and from points on the original to a
// tree of the reduced mesh.
// The sheet's search may stop short of the nearest triangle (OriginalSurface::distance2_from()): a point
// it finds over `limit` is measured again over a tree of the whole original, built only then (the
// rounded cube's edges: without it the default reduction failed four times over).
DeviationCheck sampled_check(const OriginalSurface& original, const TriangleMesh& ordered,
                             const CollapsedMesh& collapsed, const TriangleMesh& reduced, double limit) {
  constexpr std::uint64_t kSeed = 49;
  DeviationCheck check;
  const std::vector<SurfaceSample> on_reduced =
      area_samples(positions(ordered, collapsed), collapsed.triangles, kDeviationSamplesPerSide, kSeed);
  std::vector<double> d2(on_reduced.size());  // each point's own search: the same on any thread count
  tbb::parallel_for(std::size_t{0}, d2.size(), [&](std::size_t i) {
    const auto& t = collapsed.triangles[on_reduced[i].triangle];
    d2[i] = original.distance2_from(on_reduced[i].point, {t[0], t[1], t[2]}, 0.0);
  });
  std::vector<std::size_t> over;
  for (std::size_t i = 0; i < d2.size(); ++i)
    if (d2[i] > limit * limit) over.push_back(i);
  if (!over.empty()) {
    const MeshSurface whole(ordered);
    tbb::parallel_for(std::size_t{0}, over.size(), [&](std::size_t k) {
      const double d = whole.distance(on_reduced[over[k]].point);
      d2[over[k]] = std::min(d2[over[k]], d * d);
    });
  }
  check.reduced_to_full = std::sqrt(*std::max_element(d2.begin(), d2.end()));
  const MeshSurface surface(reduced);
  const std::vector<SurfaceSample> on_full =
      area_samples(ordered.vertices, ordered.triangles, kDeviationSamplesPerSide, other_side_seed(kSeed));
  check.full_to_reduced = largest_over(on_full.size(), 0.0, [&](std::size_t i, double d) {
    return std::max(d, surface.distance(on_full[i].point));
  });
  check.samples = 2 * kDeviationSamplesPerSide;
  return check;
}

// reduced_distance() measured exactly, where it came out over `limit`: the sheet's search from a
// triangle's corners gives up after some thousands of triangles (OriginalSurface::distance2_from()),
// and the flat faces of a rounded cube collapse to triangles tens of millimetres across, whose
// centroids it then put 1.5 mm off (the default reduction failed four times over). A tree over the
// whole original measures the centroids and midpoints; the vertices as before.
double exact_reduced_distance(const TriangleMesh& original, const TriangleMesh& reduced,
                              const CollapsedMesh& collapsed, double limit) {
  const MeshSurface whole(original);
  const std::vector<Vec3>& at = positions(original, collapsed);
  const double to_original = largest_over(collapsed.triangles.size(), 0.0, [&](std::size_t f, double d) {
    const auto& t = collapsed.triangles[f];
    const Vec3 &a = at[t[0]], &b = at[t[1]], &c = at[t[2]];
    for (const Vec3& p :
         {Vec3((a + b + c) / 3.0), Vec3((a + b) / 2.0), Vec3((b + c) / 2.0), Vec3((c + a) / 2.0)})
      d = std::max(d, whole.distance(p));
    return d;
  });
  return std::max(to_original, searched_vertex_distance(original, reduced, collapsed.carrier, limit));
}

// Interleaves the bits of three 21-bit integers (a Morton code).
std::uint64_t spread_bits(std::uint64_t x) {
  x &= 0x1fffff;
  x = (x | x << 32) & 0x1f00000000ffffULL;
  x = (x | x << 16) & 0x1f0000ff0000ffULL;
  x = (x | x << 8) & 0x100f00f00f00f00fULL;
  x = (x | x << 4) & 0x10c30c30c30c30c3ULL;
  x = (x | x << 2) & 0x1249249249249249ULL;
  return x;
}

// The mesh with its vertices in Morton order and its triangles in the order of their first new vertex:
// neighbours on the surface are then mostly near in memory too, where in an isosurface's order (grid
// rows) or a file's (sorted by x) a vertex's neighbours across rows lie a row or a slice away. The
// collapses mostly wait on memory (perf: the fan walks' and the quadrics' loads), and go in vertex
// order among equal keys. On the bunny's shell (1.5 M triangles, bench_reduce in turn) the order costs
// 0.09 s and saves about twice that.
TriangleMesh spatially_ordered(const TriangleMesh& mesh) {
  Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  for (const Vec3& p : mesh.vertices) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  const double extent = (hi - lo).maxCoeff();
  const double scale = extent > 0.0 ? 2097150.0 / extent : 0.0;  // to 21 bits, the top clear of rounding
  std::vector<std::pair<std::uint64_t, std::int32_t>> order(mesh.vertices.size());
  tbb::parallel_for(std::size_t{0}, order.size(), [&](std::size_t v) {
    const Vec3 q = (mesh.vertices[v] - lo) * scale;
    order[v] = {spread_bits(static_cast<std::uint64_t>(q.x())) |
                    spread_bits(static_cast<std::uint64_t>(q.y())) << 1 |
                    spread_bits(static_cast<std::uint64_t>(q.z())) << 2,
                static_cast<std::int32_t>(v)};
  });
  tbb::parallel_sort(order.begin(), order.end());  // a total order: the same on any thread count
  TriangleMesh out;
  out.vertices.resize(order.size());
  std::vector<std::int32_t> index(order.size());
  for (std::size_t i = 0; i < order.size(); ++i) {
    index[static_cast<std::size_t>(order[i].second)] = static_cast<std::int32_t>(i);
    out.vertices[i] = mesh.vertices[static_cast<std::size_t>(order[i].second)];
  }
  // The triangles by their first new vertex, ties in their old order: a counting sort over the vertices
  // (on the bunny's shell 0.04 s, where sorting (vertex, triangle) pairs took 0.08 s).
  out.triangles.resize(mesh.triangles.size());
  std::vector<std::int32_t> first(mesh.triangles.size());
  tbb::parallel_for(std::size_t{0}, first.size(), [&](std::size_t f) {
    auto& t = out.triangles[f];
    for (int k = 0; k < 3; ++k)
      t[static_cast<std::size_t>(k)] =
          index[static_cast<std::size_t>(mesh.triangles[f][static_cast<std::size_t>(k)])];
    first[f] = std::min({t[0], t[1], t[2]});
  });
  std::vector<std::uint32_t> start(order.size() + 1, 0);
  for (const std::int32_t v : first) ++start[static_cast<std::size_t>(v) + 1];
  for (std::size_t v = 0; v < order.size(); ++v) start[v + 1] += start[v];
  std::vector<Triangle> sorted(out.triangles.size());
  for (std::size_t f = 0; f < first.size(); ++f)
    sorted[start[static_cast<std::size_t>(first[f])]++] = out.triangles[f];
  out.triangles = std::move(sorted);
  return out;
}

void check_result(const MeshTopology& before, const MeshTopology& after, double volume_tolerance) {
  if (const std::string problem = printability_failures(after); !problem.empty())
    throw std::runtime_error("mesh decimation produced " + problem);
  if (after.euler_characteristic != before.euler_characteristic || after.components != before.components)
    throw std::runtime_error("mesh decimation changed the topology: Euler characteristic " +
                             std::to_string(before.euler_characteristic) + " -> " +
                             std::to_string(after.euler_characteristic) + ", components " +
                             std::to_string(before.components) + " -> " + std::to_string(after.components));
  if (std::abs(after.signed_volume - before.signed_volume) > volume_tolerance)
    throw std::runtime_error("mesh decimation changed the volume from " +
                             std::to_string(before.signed_volume) + " to " +
                             std::to_string(after.signed_volume));
}

}  // namespace

DecimateResult decimate_mesh(TriangleMesh& mesh, const DecimateOptions& options) {
  validate(options);
  DecimateResult result;
  result.triangles_before = result.triangles_after = static_cast<std::int64_t>(mesh.triangles.size());
  result.reached_target = result.triangles_before <= options.max_triangles;
  if (result.reached_target) return result;

  // Sorting and searching by position need numbers (no tree over the mesh checks them any more).
  for (const Vec3& p : mesh.vertices)
    if (!p.allFinite())
      throw InputError("the mesh has a vertex with a NaN or infinite coordinate: repair the mesh");
  const StageProgress& progress = options.progress;
  check_vertex_indices(mesh.vertices.size(), mesh.triangles, "analyze_topology");
  // The collapses work on the mesh in Morton order (spatially_ordered()).
  const TriangleMesh ordered = spatially_ordered(mesh);
  // One set of vertex -> triangle rows for the checks, the corner table and the original surface.
  VertexTriangles around = vertex_triangles(ordered.vertices.size(), ordered.triangles);
  const MeshTopology before = analyze_topology(ordered, around, progress.part(0.0, 0.05));
  if (const std::string problem = printability_failures(before); !problem.empty())
    throw std::runtime_error(
        "mesh decimation needs a closed, manifold, outward oriented mesh; this one has " + problem);
  // The surfaces are at most max_distance apart, so the volume between them is at most about
  // max_distance * area.
  const double volume_tolerance = options.max_distance * surface_area(ordered);
  const std::vector<std::int32_t> opposite = opposite_corners(ordered, around);
  const OriginalSurface original(ordered, opposite, std::move(around));
  progress.advance(0.03);

  double tolerance = options.max_distance * (options.rule == DistanceRule::kPlaced ? kPlacedShare : 1.0);
  // A budget placed collapses would reach: by the fans' bounds first where they may (attempt -1).
  const bool bounds_first = options.rule == DistanceRule::kPlaced &&
                            static_cast<double>(options.max_triangles) >=
                                kBoundsFirstShare * static_cast<double>(result.triangles_before);
  const double start = bounds_first ? 0.25 : 0.03;
  for (int attempt = bounds_first ? -1 : 0; attempt < kAttempts; ++attempt) {
    // The collapses are nearly all of the time, and attempts after the first are rare: the first gets
    // the share up to 0.97, each later one half of what is left.
    const StageProgress part =
        attempt < 0 ? progress.part(0.03, start)
                    : progress.part(attempt == 0 ? start : 1.0 - 0.03 * std::pow(0.5, attempt - 1),
                                    1.0 - 0.03 * std::pow(0.5, attempt));
    CollapseCounts counts;
    // The last attempt takes the fans' bounds alone, which hold at every point, at the bound asked: a
    // safety net, where the checked collapses overshot the sampled check three times.
    const bool last = attempt + 1 == kAttempts, by_bounds = last || attempt < 0;
    const DistanceRule rule = by_bounds ? DistanceRule::kBoundOnly : options.rule;
    const CollapsedMesh collapsed =
        rule == DistanceRule::kPlaced
            ? collapse_edges_placed(ordered, opposite, original, options.max_triangles, tolerance, counts,
                                    part.part(0.0, 0.95))
            : collapse_edges(ordered, opposite, original, options.max_triangles,
                             by_bounds ? options.max_distance : tolerance, rule, counts,
                             part.part(0.0, 0.95));
    if (attempt < 0 && static_cast<std::int64_t>(collapsed.triangles.size()) > options.max_triangles)
      continue;  // short of the budget: placed collapses, from the input
    TriangleMesh reduced = compact(ordered, collapsed);
    part.advance(0.96);
    // Both ways: the original vertices, a dense sampling of it, to the reduced surface as well.
    double distance = reduced_distance(original, ordered, reduced, collapsed, options.max_distance);
    if (distance > options.max_distance)
      distance = exact_reduced_distance(ordered, reduced, collapsed, options.max_distance);
    part.advance(0.99);
    if (distance > options.max_distance) {
      if (attempt >= 0) tolerance *= 0.9 * options.max_distance / distance;
      continue;
    }
    // The collapses' points miss some of a triangle's stray (issue 49: 0.22 mm against 0.05 on the pores'
    // rims): the sampled check, at points the collapses never chose, has the last word.
    const DeviationCheck sampled = sampled_check(original, ordered, collapsed, reduced, options.max_distance);
    if (sampled.max() > options.max_distance) {
      if (attempt >= 0) tolerance *= 0.9 * options.max_distance / sampled.max();
      continue;
    }
    result.sampled = sampled;
    result.topology = analyze_topology(reduced);
    check_result(before, *result.topology, volume_tolerance);
    result.triangles_after = static_cast<std::int64_t>(reduced.triangles.size());
    result.max_distance = std::max(distance, sampled.max());
    result.collapses = counts;
    result.attempts = attempt + (bounds_first ? 2 : 1);
    result.reached_target = result.triangles_after <= options.max_triangles;
    mesh = std::move(reduced);
    return result;
  }
  throw std::runtime_error("mesh decimation could not keep the reduced surface within " +
                           std::to_string(options.max_distance) + " of the original");
}

}  // namespace poreshell
