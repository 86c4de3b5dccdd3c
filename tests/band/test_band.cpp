#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <iostream>
#include <numbers>

#include "band/band.hpp"
#include "band/operators.hpp"
#include "core/error.hpp"
#include "geometry/mesh_surface.hpp"
#include "test_meshes.hpp"

using namespace poreshell;

namespace {

const double kDelta = 1.1 * std::sqrt(3.0);

bool paper_rule(const Surface& s, const Grid& g, const Coord& c) {
  const Vec3 x = g.position(c);
  Vec3 grad;
  for (int a = 0; a < 3; ++a) {
    Vec3 e = Vec3::Zero();
    e[a] = g.h();
    grad[a] = (s.distance(x + e) - s.distance(x - e)) / (2 * g.h());
  }
  return std::abs(s.distance(x)) < kDelta * g.h() * grad.norm();
}

// A smooth function of position on the unit sphere around (0.5, 0.5, 0.5): constant along normals.
double normal_constant(const Vec3& p) {
  const Vec3 d = (p - Vec3::Constant(0.5)).normalized();
  return std::sin(3 * d.x()) * std::cos(2 * d.y()) + d.z() * d.z();
}

double max_extension_error(int n, ClosestPointRule rule) {
  const Sphere sphere(Vec3::Constant(0.5), 0.3);
  const Grid g(Vec3::Zero(), 1.0 / (n - 1), {n, n, n});
  const NarrowBand band = build_band(sphere, g, {kDelta, rule});
  std::vector<double> ext(band.extended_size());
  for (std::size_t v = 0; v < band.size(); ++v) ext[v] = normal_constant(g.position(band.voxels()[v]));
  band.fill_ghosts(ext);
  double err = 0;
  for (std::size_t gi = 0; gi < band.ghost_count(); ++gi)
    err = std::max(err, std::abs(ext[band.size() + gi] - normal_constant(g.position(band.ghosts()[gi]))));
  return err;
}

}  // namespace

// The band is exactly the paper's set { |psi| < delta |grad_h psi| }, found without visiting the
// whole grid; checked against a brute-force scan on a non-cubic grid with an offset origin.
TEST(Band, MatchesBruteForceOnNonCubicGrid) {
  const Sphere sphere(Vec3(0.3, -0.2, 1.1), 0.45);
  const Grid g(Vec3(-0.3, -0.9, 0.4), 0.05, {25, 31, 37});
  const NarrowBand band = build_band(sphere, g);
  std::size_t expected = 0;
  for (int k = 0; k < 37; ++k)
    for (int j = 0; j < 31; ++j)
      for (int i = 0; i < 25; ++i)
        if (paper_rule(sphere, g, {i, j, k})) {
          ++expected;
          EXPECT_GE(band.find({i, j, k}), 0) << i << " " << j << " " << k;
        }
  EXPECT_EQ(band.stats().closure_added, 0);
  EXPECT_EQ(band.size(), expected);
}

// A surface that counts its queries (distance and closest point each count one; both at once, one).
class CountingSphere final : public Surface {
 public:
  CountingSphere(const Vec3& c, double r) : sphere_(c, r) {}
  double distance(const Vec3& p) const override {
    ++queries;
    return sphere_.distance(p);
  }
  std::optional<Vec3> closest_point(const Vec3& p) const override {
    ++queries;
    return sphere_.closest_point(p);
  }
  bool closest_point_is_exact() const override { return true; }
  SurfaceQuery distance_and_closest_point(const Vec3& p) const override {
    ++queries;
    return {sphere_.distance(p), sphere_.closest_point(p)};
  }
  Box bounds() const override { return sphere_.bounds(); }
  std::string name() const override { return "counting sphere"; }
  mutable std::atomic<std::int64_t> queries{0};

 private:
  Sphere sphere_;
};

// Each grid point near the surface is queried once, for its distance and closest point together: the
// band rule's differences, the ghosts' stencils and the voxels' closest points read those answers. The
// points within reach span about 2.3 band thicknesses (3.3 queries per band voxel here with the
// points the scan rules out); scanning by blocks with a halo and asking again for every ghost and
// voxel took about 6.5 on the bunny.
TEST(Band, BuildQueriesEachNearPointOnce) {
  const CountingSphere counting(Vec3::Constant(0.5), 0.3);
  const Sphere sphere(Vec3::Constant(0.5), 0.3);
  const Grid g(Vec3::Zero(), 1.0 / 80, {81, 81, 81});
  const NarrowBand band = build_band(counting, g);
  const NarrowBand reference = build_band(sphere, g);
  ASSERT_EQ(band.size(), reference.size());
  const double per_voxel = static_cast<double>(counting.queries) / static_cast<double>(band.size());
  std::cout << counting.queries << " queries for " << band.size() << " band voxels: " << per_voxel << "\n";
  EXPECT_LT(per_voxel, 3.5);
  const std::vector<Vec3> cps = band.closest_points();
  ASSERT_EQ(cps.size(), band.size());
  for (std::size_t v = 0; v < band.size(); ++v)  // float offsets of at most 3.3 h
    ASSERT_LT((cps[v] - *sphere.closest_point(g.position(band.voxels()[v]))).norm(), 1e-6 * g.h()) << v;
}

// A psi steeper than a distance (|grad psi| = 1.25): what the band rule lets in beyond 1.1 delta.
class SteepSphere final : public Surface {
 public:
  SteepSphere(const Vec3& c, double r) : sphere_(c, r) {}
  double distance(const Vec3& p) const override { return 1.25 * sphere_.distance(p); }
  std::optional<Vec3> closest_point(const Vec3& p) const override { return sphere_.closest_point(p); }
  bool closest_point_is_exact() const override { return true; }
  Box bounds() const override { return sphere_.bounds(); }
  std::string name() const override { return "steep sphere"; }

 private:
  Sphere sphere_;
};

namespace {

// An open sleeve (radius 0.3, length 0.7) inside the unit box.
TriangleMesh sleeve_in_unit_box() {
  return test_support::to_triangle_mesh(test_support::open_sleeve(0.3, 0.7, 40, 12), Vec3(0.5, 0.5, 0.15));
}

}  // namespace

// The preview's scan allows |grad_h psi| up to 1.1 instead of sqrt(3): on an open mesh sleeve and a
// sphere it finds the same voxels and ghosts with a quarter fewer queries. What it gives up shows on a
// psi steeper than a distance, whose band reaches beyond 1.1 delta.
TEST(Band, LikelyGradientBoundFindsTheSameBandWithFewerQueries) {
  const TriangleMesh mesh = sleeve_in_unit_box();
  const MeshSurface surface(mesh);
  const Grid g(Vec3::Zero(), 1.0 / 70, {71, 71, 71});
  const NarrowBand exact = build_band(surface, g);
  BandOptions likely;
  likely.gradient_bound = kLikelyGradientBound;
  const NarrowBand preview = build_band(surface, g, likely);
  ASSERT_EQ(preview.size(), exact.size());
  ASSERT_EQ(preview.ghost_count(), exact.ghost_count());
  for (std::size_t v = 0; v < exact.size(); ++v)
    ASSERT_EQ(preview.find(exact.voxels()[v]), static_cast<std::int64_t>(v));

  const CountingSphere counting(Vec3::Constant(0.5), 0.3);
  const Grid fine(Vec3::Zero(), 1.0 / 80, {81, 81, 81});
  const NarrowBand all = build_band(counting, fine);
  const std::int64_t exact_queries = counting.queries.exchange(0);
  EXPECT_EQ(build_band(counting, fine, likely).size(), all.size());
  EXPECT_LT(static_cast<double>(counting.queries), 0.8 * static_cast<double>(exact_queries));

  const SteepSphere steep(Vec3::Constant(0.5), 0.3);
  EXPECT_LT(build_band(steep, fine, likely).size(), build_band(steep, fine).size());
}

namespace {

// A closed box thinner than h, its middle on grid points: there the central differences of the distance
// cancel (|grad_h psi| = 0), so the paper's rule alone would leave points on the surface out of the band.
TriangleMesh thin_plate_in_unit_box(double thickness) {
  TriangleMesh mesh;
  for (int c = 0; c < 8; ++c)
    mesh.vertices.emplace_back(c & 1 ? 0.8 : 0.2, c & 2 ? 0.8 : 0.2, 0.5 + (c & 4 ? 0.5 : -0.5) * thickness);
  mesh.triangles = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                    {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  return mesh;
}

// A preview's surface layer is the band's voxels that carry surface area, with their distances and closest
// points, neighbours within the layer and no ghosts; its scan asks the surface far fewer times.
void expect_layer_is_band_where_it_carries_area(const TriangleMesh& mesh, const Grid& g) {
  const MeshSurface surface(mesh);
  const NarrowBand band = build_band(surface, g);
  BandOptions only_area;
  only_area.surface_layer = true;
  const NarrowBand layer = build_band(surface, g, only_area);
  EXPECT_EQ(layer.ghost_count(), 0u);
  std::size_t carrying = 0;
  for (std::size_t v = 0; v < band.size(); ++v) {
    if (!(band.surface_area(v) > 0.0)) {
      EXPECT_LT(layer.find(band.voxels()[v]), 0);
      continue;
    }
    const std::int64_t l = layer.find(band.voxels()[v]);
    ASSERT_GE(l, 0);
    const auto u = static_cast<std::size_t>(l);
    EXPECT_EQ(layer.distance()[u], band.distance()[v]);
    EXPECT_EQ(layer.closest_point(u), band.closest_point(v));
    ++carrying;
  }
  ASSERT_EQ(layer.size(), carrying);
  for (std::size_t v = 0; v < layer.size(); ++v)
    for (int n = 0; n < NarrowBand::kNeighbors; ++n) {
      const Coord c = shifted(layer.voxels()[v], kFaceOffsets[static_cast<std::size_t>(n)]);
      EXPECT_EQ(layer.neighbor(v, n), layer.find(c));
    }
  // Every grid point within h of the surface is a band voxel (the brute-force check).
  std::size_t within_h = 0;
  for (int k = 0; k < g.dims()[2]; ++k)
    for (int j = 0; j < g.dims()[1]; ++j)
      for (int i = 0; i < g.dims()[0]; ++i)
        if (surface.distance(g.position({i, j, k})) < g.h()) {
          ++within_h;
          EXPECT_GE(band.find({i, j, k}), 0) << i << " " << j << " " << k;
        }
  EXPECT_EQ(layer.size(), within_h);
}

}  // namespace

TEST(Band, SurfaceLayerIsTheBandWhereItCarriesArea) {
  const Grid g(Vec3::Zero(), 1.0 / 70, {71, 71, 71});
  expect_layer_is_band_where_it_carries_area(sleeve_in_unit_box(), g);
  expect_layer_is_band_where_it_carries_area(thin_plate_in_unit_box(0.8 * g.h()), g);
  BandOptions only_area;
  only_area.surface_layer = true;

  // Against the band a preview built before, with the likely gradient bound: its points within reach
  // are a third, its queries in all (the blocks' included) about half.
  const CountingSphere counting(Vec3::Constant(0.5), 0.3);
  const Grid fine(Vec3::Zero(), 1.0 / 80, {81, 81, 81});
  BandOptions likely;
  likely.gradient_bound = kLikelyGradientBound;
  static_cast<void>(build_band(counting, fine, likely));
  const std::int64_t band_queries = counting.queries.exchange(0);
  static_cast<void>(build_band(counting, fine, only_area));
  EXPECT_LT(static_cast<double>(counting.queries), 0.6 * static_cast<double>(band_queries));
}

TEST(Band, SizeIsAreaTimesThickness) {
  const int n = 131;
  const Grid g(Vec3::Zero(), 1.0 / (n - 1), {n, n, n});
  const NarrowBand band = build_band(*make_paper_shape("sphere"), g);
  // {|psi| < delta} for the exact distance: a shell of volume 4 pi R^2 * 2 delta (1 + O(delta^2/R^2)).
  const double h = g.h(), R = 0.3;
  const double expected = 4 * std::numbers::pi * R * R * 2 * kDelta * h / (h * h * h);
  EXPECT_NEAR(static_cast<double>(band.size()) / expected, 1.0, 0.03);
  // The builder skipped almost every 8^3 block of the grid.
  EXPECT_LT(band.stats().candidate_blocks, (n / 8 + 1) * (n / 8 + 1) * (n / 8 + 1) / 4);
  EXPECT_LT(band.memory_bytes(), band.size() * 200);
}

TEST(Band, GhostsCloseTheLaplacianStencil) {
  const int n = 41;
  const Grid g(Vec3::Zero(), 1.0 / (n - 1), {n, n, n});
  const NarrowBand band = build_band(*make_paper_shape("torus"), g);
  const auto nb = static_cast<std::int32_t>(band.size());
  std::vector<int> ghost_used(band.ghost_count(), 0);
  for (std::size_t v = 0; v < band.size(); ++v)
    for (int k = 0; k < NarrowBand::kNeighbors; ++k) {
      const std::int32_t idx = band.neighbor(v, k);
      ASSERT_GE(idx, 0);
      ASSERT_LT(idx, static_cast<std::int32_t>(band.extended_size()));
      const Coord c = band.voxels()[v];
      const int axis = k / 2, step = (k % 2) ? 1 : -1;
      const Coord expected{c.i + (axis == 0 ? step : 0), c.j + (axis == 1 ? step : 0),
                           c.k + (axis == 2 ? step : 0)};
      const Coord at = idx < nb ? band.voxels()[static_cast<std::size_t>(idx)]
                                : band.ghosts()[static_cast<std::size_t>(idx - nb)];
      EXPECT_TRUE(at.i == expected.i && at.j == expected.j && at.k == expected.k) << "neighbour " << k;
      if (idx >= nb) ++ghost_used[static_cast<std::size_t>(idx - nb)];
    }
  for (int parity = 0; parity < 2; ++parity) {
    const auto [begin, end] = band.ghosts_of_parity(parity);
    EXPECT_LT(begin, end);
    for (std::size_t gi = begin; gi < end; ++gi) {
      const Coord c = band.ghosts()[gi];
      EXPECT_EQ((c.i + c.j + c.k) & 1, parity);
    }
  }
  for (std::size_t gi = 0; gi < ghost_used.size(); ++gi) {
    EXPECT_GT(ghost_used[gi], 0);
    EXPECT_LT(band.find(band.ghosts()[gi]), 0);  // ghosts are outside the band
  }
  // The paper's I|grad_h I| != 0 set is contained in ours; ours also holds the few balanced points.
  EXPECT_LE(band.stats().paper_ghosts, static_cast<std::int64_t>(band.ghost_count()));
  EXPECT_GT(band.stats().paper_ghosts, static_cast<std::int64_t>(band.ghost_count() * 9 / 10));
}

TEST(Band, StencilsInterpolateLinearFunctionsExactlyAtTheClosestPoint) {
  const int n = 49;
  const Grid g(Vec3::Zero(), 1.0 / (n - 1), {n, n, n});
  const auto torus = make_paper_shape("torus");
  const NarrowBand band = build_band(*torus, g);
  const auto linear = [](const Vec3& p) { return 0.3 + 2.0 * p.x() - 1.5 * p.y() + 0.7 * p.z(); };
  constexpr double kLinearSlope = 2.0 + 1.5 + 0.7;  // bounds |grad . d| / |d|_inf
  std::vector<double> ext(band.extended_size());
  for (std::size_t v = 0; v < band.size(); ++v) ext[v] = linear(g.position(band.voxels()[v]));
  band.fill_ghosts(ext);
  for (std::size_t gi = 0; gi < band.ghost_count(); ++gi) {
    const GhostStencil& s = band.stencils()[gi];
    double wsum = 0;
    for (int c = 0; c < 8; ++c) {
      EXPECT_GE(s.weight(c), -1e-15);
      wsum += s.weight(c);
      // Corner c is the voxel (di, dj, dk) from corner 0: the compact stencil's x-neighbour rule holds.
      const Coord base = band.voxels()[static_cast<std::size_t>(s.corner(0))];
      const Coord at = band.voxels()[static_cast<std::size_t>(s.corner(c))];
      EXPECT_EQ(at.i - base.i, c & 1);
      EXPECT_EQ(at.j - base.j, (c >> 1) & 1);
      EXPECT_EQ(at.k - base.k, c >> 2);
    }
    EXPECT_NEAR(wsum, 1.0, 1e-12);
    // Exact at the cp as stored: its position in the cell in float (within 2^-24 cells of the cp).
    const Vec3 cp = *torus->closest_point(g.position(band.ghosts()[gi]));
    EXPECT_NEAR(ext[band.size() + gi], linear(cp), kLinearSlope * g.h() * 0x1p-23);
  }
  EXPECT_GT(band.stats().max_closest_point_offset, 1.5);
  EXPECT_LT(band.stats().max_closest_point_offset, 3.5);
}

// Closest-point extension of a function constant along normals: trilinear interpolation is second order,
// with the exact closest point and with the paper's gradient formula.
TEST(Band, ClosestPointExtensionIsSecondOrder) {
  for (ClosestPointRule rule : {ClosestPointRule::exact, ClosestPointRule::paper_gradient}) {
    const double coarse = max_extension_error(33, rule), fine = max_extension_error(65, rule);
    EXPECT_GT(std::log2(coarse / fine), 1.7) << coarse << " " << fine;
    EXPECT_LT(fine, 5e-3);
  }
}

// The matrix form of Delta_h (ghosts eliminated) equals the stencil form, and constants are in its kernel.
TEST(Band, LaplacianMatrixMatchesStencilAndAnnihilatesConstants) {
  const int n = 33;
  const Grid g(Vec3::Zero(), 1.0 / (n - 1), {n, n, n});
  const NarrowBand band = build_band(*make_paper_shape("sphere"), g);
  const SparseMatrix L = laplacian_matrix(band);
  std::vector<double> ext(band.extended_size());
  for (std::size_t v = 0; v < band.size(); ++v) ext[v] = normal_constant(g.position(band.voxels()[v]));
  band.fill_ghosts(ext);
  std::vector<double> out(band.size());
  apply_laplacian(band, ext, out);
  const Eigen::VectorXd x =
      Eigen::Map<const Eigen::VectorXd>(ext.data(), static_cast<Eigen::Index>(band.size()));
  const Eigen::VectorXd y = L * x;
  for (std::size_t v = 0; v < band.size(); ++v) EXPECT_NEAR(y[static_cast<Eigen::Index>(v)], out[v], 1e-9);
  const Eigen::VectorXd ones = Eigen::VectorXd::Ones(static_cast<Eigen::Index>(band.size()));
  EXPECT_LT((L * ones).lpNorm<Eigen::Infinity>(), 1e-9);
}

TEST(Band, RefusesABandThatTouchesTheGridEdge) {
  const Sphere sphere(Vec3::Constant(0.5), 0.49);
  const Grid g(Vec3::Zero(), 1.0 / 32, {33, 33, 33});
  EXPECT_THROW(build_band(sphere, g), InputError);
  const Sphere outside(Vec3::Constant(5.0), 0.3);
  EXPECT_THROW(build_band(outside, g), InputError);
}
