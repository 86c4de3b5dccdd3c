#pragma once
// The hole layout as a centroidal Voronoi tessellation (issue 19): Lloyd's iteration of the hole
// centres over area samples of the surface, the discs the equation restarts from, and how even a
// layout is (its Voronoi cells' areas on the surface).

#include <optional>
#include <span>
#include <vector>

#include "band/band.hpp"
#include "core/types.hpp"
#include "geometry/surface.hpp"
#include "pattern/solid_zones.hpp"

namespace poreshell {

// The surface as weighted points: each band voxel within h of the surface gives its closest point with
// the area it carries, h^2 (1 - |psi| / h) (as pattern.cpp's hole areas). Voxels whose solid-zone
// weight (empty: none) is 1/2 or more give none: no hole may sit there.
struct AreaSamples {
  std::vector<Vec3> points;
  std::vector<double> area;
  std::vector<std::int32_t> voxel;  // the band voxel each comes from
};
// Samples closer than `margin` to a zone's give none either (the equation keeps its spots off zones).
AreaSamples area_samples(const NarrowBand& band, std::span<const double> zone_weight = {},
                         double margin = 0.0);

// Each sample's nearest centre (ties: the lower index). Parallel, deterministic.
std::vector<std::int32_t> nearest_centres(const AreaSamples& samples, std::span<const Vec3> centres);

// The coefficient of variation of the centres' Voronoi cell areas on the surface (the samples' areas
// summed per nearest centre). 0 for fewer than two centres.
double cell_area_cv(const AreaSamples& samples, std::span<const Vec3> centres);

// Lloyd's iteration (over-relaxed): each centre moves towards its cell's area centroid, projected onto
// the surface;
// centres whose cell holds no area are dropped. Sums in sample order: the same result on any thread
// count.
std::vector<Vec3> lloyd_centres(std::vector<Vec3> centres, const AreaSamples& samples, const Surface& surface,
                                int iterations);

// Evens out the distances between neighbouring centres, which Lloyd's iteration leaves uneven where its
// tessellation settles with dislocations (pairs of 5- and 7-neighbour cells): each iteration pushes a
// centre away from those of its 6 nearest that are closer than the mean distance to them, projected
// onto the surface. Centres with less free area than a full disc of radius `spacing` around them (near a
// solid zone or an open edge) stay where they are; a move that takes a centre further than `reach` from
// every sample (out of the free area), or further than 0.2 spacing from where it started, is not taken.
// Deterministic, on any thread count.
std::vector<Vec3> spread_centres(std::vector<Vec3> centres, const AreaSamples& samples,
                                 const Surface& surface, double spacing, double reach, int iterations);

// The samples split into the free surface's connected parts (through neighbouring band voxels), in the
// order of their first samples. Lloyd's iteration moves no centre from one part to another, so each part
// must start with the centres its own area asks for.
std::vector<AreaSamples> free_parts(const NarrowBand& band, const AreaSamples& samples);

// `count` well-spread starting centres among the samples: the seed picks the first (area-weighted), each
// next one is the sample farthest from those chosen. Deterministic for a seed.
std::vector<Vec3> farthest_point_centres(const AreaSamples& samples, std::size_t count, std::uint64_t seed);

// The hole centres of an even layout at the equation's own density for `spacing` (grid units): each free
// part's area gives its count, the farthest-point start spreads them within it, Lloyd's iteration makes them
// a centroidal Voronoi tessellation, spread_centres evens out their distances and two more Lloyd iterations
// settle them for the equation. Deterministic for a seed, on any thread count.
std::vector<Vec3> even_layout(const NarrowBand& band, const Surface& surface,
                              std::span<const double> zone_weight, double spacing, std::uint64_t seed);

// The centres at least `clearance` from every open edge (all in grid units). A disc whose pore comes
// nearer an open edge than half an interface width is not a hole the equation keeps: on the bunny's
// base (8 mm holes at 14 mm) the discs centred 3.9 and 4.1 mm from its open edges closed, those
// 5.0-5.4 mm away stayed (4.55-4.92 mm: either, by seed), and nearer ones are notches cut into the
// edge, not holes. The layout is the
// preview's prediction of the holes (docs/solver.md "Layout", step 5).
std::vector<Vec3> clear_of_open_edges(std::vector<Vec3> centres, std::span<const Segment> open_edges,
                                      double clearance);

// The centres with each pair closer than `diameter` (the discs' pores overlap, painting one spot) merged
// into one at their midpoint on the surface, closest pairs first, until none is. The equation rounds
// such a spot into one hole of about one disc's size: on the bunny's ear (8 mm holes at 14 mm, seeds
// 1-5), before the layout counted its centres per free part, two or three centres closer than 8 mm
// painted a spot of 11.1-13.3 mm where the run made one 7.1 mm hole (docs/solver.md "Layout", the
// preview). The bunny has no such pair now; a free part too narrow for Lloyd's cells to be round may.
// For a preview, which shows the discs as placed.
std::vector<Vec3> merge_overlapping_centres(std::vector<Vec3> centres, double diameter,
                                            const Surface& surface);

// Discs of `radius` at `centres`, each voxel judged by its closest point: the equation's interface
// profile tanh(x / (sqrt 2 epsilon)) across the disc's edge (+1 inside: a pore); solid (-1) where the
// zone weight (empty: none) is 1, blended as the run's start is; then the free part shifted so that the
// band's mean is `mean`, if given. The equation conserves the mean, and its nonlocal term has a
// solution only for the mean it started from: give the mean of the field this one replaces (none for
// discs that are shown, not solved: the shift moves their edges).
std::vector<double> disc_field(const NarrowBand& band, std::span<const Vec3> centres, double radius,
                               double epsilon, std::span<const double> zone_weight,
                               std::optional<double> mean);

}  // namespace poreshell
