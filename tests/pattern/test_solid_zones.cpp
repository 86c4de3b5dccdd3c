// Solid zones (issue 4, item 5): a rim along an open sheet's boundary and keep-out spheres hold no pore,
// because the local mean concentration there is the solid phase, and the pattern forms around them.

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "band/band.hpp"
#include "geometry/mesh_surface.hpp"
#include "pattern/pattern.hpp"
#include "pattern/solid_zones.hpp"
#include "solver/fast_solver.hpp"
#include "solver/initial_condition.hpp"
#include "solver/time_stepping.hpp"

using namespace poreshell;

namespace {

constexpr int kN = 65;
const Vec3 kCenter = Vec3::Constant(0.5);
constexpr double kRadius = 0.3;

Grid unit_grid() {
  return Grid(Vec3::Zero(), 1.0 / (kN - 1), {kN, kN, kN});
}

// A spherical cap over polar angles [0, max_angle]: an open sheet with one boundary circle.
TriangleMesh spherical_cap(double max_angle, int rings, int segments) {
  TriangleMesh m;
  m.vertices.push_back(kCenter + Vec3(0, 0, kRadius));
  for (int r = 1; r <= rings; ++r) {
    const double theta = max_angle * r / rings;
    for (int s = 0; s < segments; ++s) {
      const double phi = 2 * std::numbers::pi * s / segments;
      m.vertices.push_back(kCenter + kRadius * Vec3(std::sin(theta) * std::cos(phi),
                                                    std::sin(theta) * std::sin(phi), std::cos(theta)));
    }
  }
  auto at = [&](int r, int s) { return r == 0 ? 0 : 1 + (r - 1) * segments + (s % segments); };
  for (int s = 0; s < segments; ++s) m.triangles.push_back({0, at(1, s), at(1, s + 1)});
  for (int r = 1; r < rings; ++r)
    for (int s = 0; s < segments; ++s) {
      m.triangles.push_back({at(r, s), at(r + 1, s), at(r + 1, s + 1)});
      m.triangles.push_back({at(r, s), at(r + 1, s + 1), at(r, s + 1)});
    }
  return m;
}

// The paper's sphere parameters on this grid (alpha eps^2 kept), the fast solver with a mean field.
std::vector<double> pattern_with_zones(const NarrowBand& band, const std::vector<double>& weight) {
  const double eps = epsilon_m(4, band.grid().h());
  const ModelParameters model{0.0764 / (eps * eps), eps, -0.3};
  FastSolver solver(band, model, 100 * band.grid().h());
  solver.set_mean_field(mean_concentration_field(weight, model.phi_bar));
  std::vector<double> phi = random_initial_condition(band, -0.3, 0.5, 1);
  for (std::size_t v = 0; v < phi.size(); ++v) phi[v] = (1 - weight[v]) * phi[v] - weight[v];
  RunOptions options;
  options.max_steps = 1500;
  options.min_spread = 1.0;
  EXPECT_TRUE(run_to_steady_state(solver, phi, nullptr, options).reached_tolerance);
  return phi;
}

}  // namespace

TEST(SolidZones, BoundarySegmentsAreTheEdgesWithOneTriangle) {
  const TriangleMesh cap = spherical_cap(std::numbers::pi / 2, 4, 12);
  EXPECT_EQ(boundary_segments(cap).size(), 12u);  // the rim circle
  TriangleMesh square;
  square.vertices = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0)};
  square.triangles = {{0, 1, 2}, {0, 2, 3}};
  EXPECT_EQ(boundary_segments(square).size(), 4u);  // the diagonal is shared
}

TEST(SolidZones, RimAlongAnOpenSheetHoldsNoPore) {
  const TriangleMesh cap = spherical_cap(0.6 * std::numbers::pi, 48, 192);
  const MeshSurface surface(cap);
  const NarrowBand band = build_band(surface, unit_grid());
  const std::vector<Segment> boundary = boundary_segments(cap);
  const double h = band.grid().h(), rim = 4 * h;
  const std::vector<double> weight = solid_zone_weight(band, boundary, rim, {}, 2 * h);
  const std::vector<double> phi = pattern_with_zones(band, weight);

  double closest_pore = 1e9;
  for (std::size_t v = 0; v < phi.size(); ++v) {
    if (!(phi[v] > 0.0)) continue;
    const Vec3 x = band.grid().position(band.voxels()[v]);
    for (const Segment& s : boundary) closest_pore = std::min(closest_pore, segment_distance(x, s));
  }
  const SpotStats spots = spot_statistics(band, phi, 0.0);
  std::printf("cap with a %.0f h rim: %lld spots, nearest pore voxel %.2f h from the boundary\n", rim / h,
              static_cast<long long>(spots.count), closest_pore / h);
  EXPECT_GT(spots.count, 5);
  EXPECT_GE(closest_pore, rim);
}

TEST(SolidZones, KeepOutSpheresHoldNoPore) {
  const Sphere surface(kCenter, kRadius);
  const NarrowBand band = build_band(surface, unit_grid());
  const double h = band.grid().h();
  const std::vector<SolidSphere> keep_out{{kCenter + Vec3(0, 0, kRadius), 0.12},
                                          {kCenter + Vec3(kRadius, 0, 0), 0.08}};
  const std::vector<double> weight = solid_zone_weight(band, {}, 0.0, keep_out, 2 * h);
  const std::vector<double> phi = pattern_with_zones(band, weight);
  std::int64_t pore_voxels_inside = 0;
  for (std::size_t v = 0; v < phi.size(); ++v) {
    const Vec3 x = band.grid().position(band.voxels()[v]);
    for (const SolidSphere& k : keep_out)
      if ((x - k.center).norm() <= k.radius && phi[v] > 0.0) ++pore_voxels_inside;
  }
  const SpotStats spots = spot_statistics(band, phi, 0.0);
  std::printf("sphere with two keep-out zones: %lld spots\n", static_cast<long long>(spots.count));
  EXPECT_EQ(pore_voxels_inside, 0);
  EXPECT_GT(spots.count, 15);  // about 31 without the zones
}

TEST(SolidZones, KeepOutBoxHoldsNoPore) {
  const Sphere surface(kCenter, kRadius);
  const NarrowBand band = build_band(surface, unit_grid());
  const double h = band.grid().h();
  // A slab across the sphere's equator, as a strap would need.
  const std::vector<SolidBox> boxes{{kCenter - Vec3(0.4, 0.4, 0.05), kCenter + Vec3(0.4, 0.4, 0.05)}};
  const std::vector<double> weight = solid_zone_weight(band, {}, 0.0, {}, 2 * h, boxes);
  const std::vector<double> phi = pattern_with_zones(band, weight);
  std::int64_t pore_voxels_inside = 0, voxels_inside = 0;
  for (std::size_t v = 0; v < phi.size(); ++v) {
    const Vec3 x = band.grid().position(band.voxels()[v]);
    if ((x - boxes[0].min).minCoeff() >= 0 && (boxes[0].max - x).minCoeff() >= 0) {
      ++voxels_inside;
      if (phi[v] > 0.0) ++pore_voxels_inside;
    }
  }
  EXPECT_GT(voxels_inside, 1000);
  EXPECT_EQ(pore_voxels_inside, 0);
  EXPECT_GT(spot_statistics(band, phi, 0.0).count, 15);
}
