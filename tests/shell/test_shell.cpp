// The printable shell: wall thickness measured on the output mesh (sphere and open sheet, every
// offset), pores counted by the Euler characteristic against the band's spots, determinism, sparse
// sampling; the winding number that tells inside from outside (closed mesh, open sheet, the bunny).
// Patterns are made by hand (analytic spots), not by the solver, so the file runs in seconds.

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <optional>
#include <random>

#include "band/band.hpp"
#include "core/error.hpp"
#include "geometry/isosurface.hpp"
#include "geometry/mesh_surface.hpp"
#include "geometry/winding_number.hpp"
#include "io/mesh_io.hpp"
#include "pattern/pattern.hpp"
#include "shell/shell.hpp"
#include "test_meshes.hpp"

namespace poreshell {
namespace {

const Vec3 kCenter = Vec3::Constant(0.5);
constexpr double kRadius = 0.3;
constexpr int kN = 65;

Grid unit_grid() {
  return Grid::fitted(Box{Vec3::Zero(), Vec3::Ones()}, kN);
}

// Distance along the ray p + s u (s > 0) to every triangle it crosses (Moller-Trumbore), sorted.
std::vector<double> ray_hits(const TriangleMesh& mesh, const Vec3& p, const Vec3& u) {
  std::vector<double> hits;
  for (const auto& t : mesh.triangles) {
    const Vec3 &a = mesh.vertices[t[0]], &b = mesh.vertices[t[1]], &c = mesh.vertices[t[2]];
    const Vec3 e1 = b - a, e2 = c - a, q = u.cross(e2);
    const double det = e1.dot(q);
    if (std::abs(det) < 1e-14) continue;
    const Vec3 s = p - a;
    const double v = s.dot(q) / det;
    const Vec3 r = s.cross(e1);
    const double w = u.dot(r) / det;
    if (v < 0 || w < 0 || v + w > 1) continue;
    const double dist = e2.dot(r) / det;
    if (dist > 0) hits.push_back(dist);
  }
  std::sort(hits.begin(), hits.end());
  return hits;
}

// Pores: smooth spots of geodesic radius `spot` around `centers` (unit directions from kCenter), phi > 0
// inside a spot, -1 far from every spot.
struct SpherePattern {
  std::vector<Vec3> centers;
  double spot = 0.0, width = 0.0;
  double at(const Vec3& x) const {
    const Vec3 u = (x - kCenter).normalized();
    double g = INFINITY;
    for (const Vec3& c : centers) g = std::min(g, kRadius * std::acos(std::clamp(u.dot(c), -1.0, 1.0)));
    return std::tanh((spot - g) / width);
  }
  double clearance(const Vec3& u) const {  // geodesic distance from direction u to the nearest spot's edge
    double g = INFINITY;
    for (const Vec3& c : centers) g = std::min(g, kRadius * std::acos(std::clamp(u.dot(c), -1.0, 1.0)));
    return g - spot;
  }
};

// 12 spots at the vertices of an icosahedron: 0.33 apart on the sphere, radius 0.06.
SpherePattern icosahedron_spots() {
  const double g = (1.0 + std::sqrt(5.0)) / 2.0;
  SpherePattern p;
  for (double s : {-1.0, 1.0})
    for (double r : {-1.0, 1.0}) {
      p.centers.push_back(Vec3(0, s, r * g).normalized());
      p.centers.push_back(Vec3(s, r * g, 0).normalized());
      p.centers.push_back(Vec3(r * g, 0, s).normalized());
    }
  p.spot = 0.06;
  p.width = 0.02;
  return p;
}

std::vector<double> band_values(const NarrowBand& band, const std::function<double(const Vec3&)>& f) {
  std::vector<double> phi(band.size());
  for (std::size_t v = 0; v < band.size(); ++v) phi[v] = f(band.grid().position(band.voxels()[v]));
  return phi;
}

void expect_printable(const MeshTopology& t) {
  EXPECT_GT(t.triangles, 0);
  EXPECT_TRUE(t.closed()) << t.boundary_edges << " boundary edges";
  EXPECT_TRUE(t.manifold());
  EXPECT_TRUE(t.oriented());
  EXPECT_EQ(t.degenerate_triangles, 0);
  EXPECT_GT(t.signed_volume, 0.0);
}

struct SphereCase {
  Grid grid = unit_grid();
  Sphere sphere{kCenter, kRadius};
  NarrowBand band = build_band(sphere, grid);
  SpherePattern pattern = icosahedron_spots();
  std::vector<double> phi = band_values(band, [this](const Vec3& x) { return pattern.at(x); });
};

ShellOptions options(double t, WallOffset offset, double h) {
  ShellOptions o;
  o.thickness = t;
  o.offset = offset;
  o.pattern_length = h;
  return o;
}

TEST(Shell, SphereWallThicknessAndPlacementFollowTheRequest) {
  const SphereCase s;
  const double h = s.grid.h();
  std::mt19937 rng(7);
  std::normal_distribution<double> normal;
  for (double t : {1.5 * h, 4.0 * h, 8.0 * h})
    for (WallOffset offset : {WallOffset::centered, WallOffset::inside, WallOffset::outside}) {
      const ShellSamples samples = sample_shell(s.sphere, s.band, s.phi, options(t, offset, h));
      const TriangleMesh mesh = shell_mesh(samples, 0.0);
      expect_printable(analyze_topology(mesh));
      const double mid = kRadius + (offset == WallOffset::inside    ? -0.5 * t
                                    : offset == WallOffset::outside ? 0.5 * t
                                                                    : 0.0);
      double worst = 0.0;
      int rays = 0;
      while (rays < 40) {
        const Vec3 u = Vec3(normal(rng), normal(rng), normal(rng)).normalized();
        if (s.pattern.clearance(u) < 3.0 * h) continue;  // away from pores and their chamfers
        const std::vector<double> hits = ray_hits(mesh, kCenter, u);
        ASSERT_EQ(hits.size(), 2u) << "t " << t / h << " h, " << to_string(offset);
        worst = std::max(worst, std::abs((hits[1] - hits[0]) - t) / t);
        EXPECT_NEAR(0.5 * (hits[0] + hits[1]), mid, 0.05 * t);
        ++rays;
      }
      std::printf("sphere, wall %.1f h %-8s: spacing %.3f h, %zu samples, worst thickness error %.2f%%\n",
                  t / h, to_string(offset).c_str(), samples.grid.h() / h, samples.points.size(), 100 * worst);
      EXPECT_LT(worst, 0.10);
      EXPECT_EQ(samples.incomplete_stencils, 0);
    }
}

TEST(Shell, PoresFromEulerEqualTheBandsSpots) {
  const SphereCase s;
  const double h = s.grid.h();
  for (double t : {2.0 * h, 5.0 * h}) {
    const ShellSamples samples = sample_shell(s.sphere, s.band, s.phi, options(t, WallOffset::centered, h));
    const MeshTopology solid = analyze_topology(unperforated_shell_mesh(samples));
    expect_printable(solid);
    EXPECT_EQ(solid.euler_characteristic, 4);  // two nested spheres
    for (double iso : {-0.3, 0.0, 0.3}) {
      const MeshTopology t_iso = analyze_topology(shell_mesh(samples, iso));
      expect_printable(t_iso);
      const std::int64_t pores = (solid.euler_characteristic - t_iso.euler_characteristic) / 2;
      EXPECT_EQ(pores, spot_statistics(s.band, s.phi, iso).count) << "iso " << iso;
      EXPECT_EQ(pores, 12);
      EXPECT_EQ(t_iso.components, 1);
    }
  }
}

TEST(Shell, SameMeshForOneAndTwoThreads) {
  const SphereCase s;
  const auto build = [&](int threads) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism,
                              static_cast<std::size_t>(threads));
    return shell_mesh(
        sample_shell(s.sphere, s.band, s.phi, options(3 * s.grid.h(), WallOffset::outside, 0.01)), 0.0);
  };
  const TriangleMesh one = build(1), two = build(2);
  EXPECT_EQ(one.triangles, two.triangles);
  EXPECT_EQ(one.vertices, two.vertices);
}

TEST(Shell, SamplesGrowWithTheAreaNotTheBox) {
  const SphereCase s;
  const double h = s.grid.h();
  for (double t : {2.0 * h, 8.0 * h}) {
    const ShellSamples samples = sample_shell(s.sphere, s.band, s.phi, options(t, WallOffset::centered, h));
    const double hs = samples.grid.h();
    const double slab =
        4 * std::numbers::pi * kRadius * kRadius * (t + 2 * std::sqrt(3.0) * hs) / (hs * hs * hs);
    EXPECT_NEAR(static_cast<double>(samples.points.size()) / slab, 1.0, 0.1) << "t " << t / h << " h";
    EXPECT_LT(static_cast<double>(samples.points.size()),
              0.5 * static_cast<double>(samples.grid.cell_count()));
  }
}

// Where the shell's spacing is the band's, its samples are band grid points, and those that are band
// voxels take the band's closest points: the wall is the exact one either way.
TEST(Shell, SamplesOnTheBandsGridKeepTheExactWall) {
  const SphereCase s;
  const double h = s.grid.h();
  for (WallOffset offset : {WallOffset::centered, WallOffset::inside}) {
    const double t = 4.0 * h, c = offset == WallOffset::inside ? -0.5 * t : 0.0;
    const ShellSamples samples = sample_shell(s.sphere, s.band, s.phi, options(t, offset, h));
    ASSERT_EQ(samples.grid.h(), h);
    const Vec3 cells = (samples.grid.origin() - s.grid.origin()) / h;
    EXPECT_NEAR((cells - cells.array().round().matrix()).norm(), 0.0, 1e-9);
    std::int64_t band_voxels = 0;
    double worst = 0.0;
    for (std::size_t n = 0; n < samples.points.size(); ++n) {
      const Vec3 x = samples.grid.position(samples.points[n]);
      const double d = (x - kCenter).norm() - kRadius;
      worst = std::max(worst, std::abs(samples.wall[n] - (std::abs(d - c) - 0.5 * t)));
      const Vec3 q = s.grid.to_index_space(x).array().round();
      band_voxels +=
          s.band.find({static_cast<int>(q.x()), static_cast<int>(q.y()), static_cast<int>(q.z())}) >= 0;
    }
    EXPECT_GT(band_voxels, static_cast<std::int64_t>(samples.points.size() / 5));
    EXPECT_LT(worst, 1e-6 * h) << to_string(offset);
  }
}

// Every cube with a corner inside the wall has all 8 corners sampled (a missing one would take the
// background value and move the surface): the samples reach sqrt(3) cells beyond the slab.
TEST(Shell, EveryCubeTouchingTheWallIsSampled) {
  const SphereCase s;
  const double h = s.grid.h();
  for (double t : {1.5 * h, 4.0 * h})
    for (WallOffset offset : {WallOffset::centered, WallOffset::inside, WallOffset::outside}) {
      const ShellSamples samples = sample_shell(s.sphere, s.band, s.phi, options(t, offset, h));
      std::vector<std::int64_t> keys(samples.points.size());
      for (std::size_t n = 0; n < keys.size(); ++n) keys[n] = samples.grid.key(samples.points[n]);
      ASSERT_TRUE(std::is_sorted(keys.begin(), keys.end()));
      std::int64_t inside = 0, missing = 0;
      for (std::size_t n = 0; n < keys.size(); ++n) {
        if (!(samples.wall[n] < 0.0)) continue;
        ++inside;
        const Coord c = samples.points[n];
        for (int dk = -1; dk <= 1; ++dk)
          for (int dj = -1; dj <= 1; ++dj)
            for (int di = -1; di <= 1; ++di) {
              const std::int64_t key = samples.grid.key({c.i + di, c.j + dj, c.k + dk});
              missing += !std::binary_search(keys.begin(), keys.end(), key);
            }
      }
      EXPECT_GT(inside, 1000);
      EXPECT_EQ(missing, 0) << "t " << t / h << " h, " << to_string(offset);
    }
}

TEST(Shell, RejectsANonPositiveWall) {
  const SphereCase s;
  EXPECT_THROW(sample_shell(s.sphere, s.band, s.phi, options(0.0, WallOffset::centered, 0.01)), InputError);
}

// A flat square sheet in the plane z = 0.5, [0.2, 0.8]^2, normal +z, 3 x 3 round pores of radius 0.05
// (sheet_pattern).
TriangleMesh square_sheet(int n) {
  return test_support::to_triangle_mesh(test_support::square_sheet(0.2, 0.6, n, 0.5));
}

double sheet_pattern(const Vec3& x) {
  double g = INFINITY;
  for (double cx : {0.35, 0.5, 0.65})
    for (double cy : {0.35, 0.5, 0.65}) g = std::min(g, std::hypot(x.x() - cx, x.y() - cy));
  return std::tanh((0.05 - g) / 0.015);
}

TEST(Shell, OpenSheetWallFollowsTheRequestOnTheNormalsSide) {
  const TriangleMesh sheet = square_sheet(24);
  const MeshSurface surface(sheet);
  const Grid grid = unit_grid();
  const double h = grid.h();
  const NarrowBand band = build_band(surface, grid);
  const std::vector<double> phi = band_values(band, sheet_pattern);
  const WindingNumber winding(sheet);
  const MeshTopology solid_ref = [&] {
    ShellOptions o = options(3 * h, WallOffset::centered, h);
    return analyze_topology(unperforated_shell_mesh(sample_shell(surface, band, phi, o)));
  }();
  EXPECT_EQ(solid_ref.euler_characteristic, 2);  // a thick plate: one sphere

  std::mt19937 rng(3);
  std::uniform_real_distribution<double> uniform(0.25, 0.75);
  for (double t : {1.5 * h, 4.0 * h})
    for (WallOffset offset : {WallOffset::centered, WallOffset::inside, WallOffset::outside}) {
      ShellOptions o = options(t, offset, h);
      o.side = [&](const Vec3& x, const Vec3& cp) { return side_of_surface(winding, x, cp, 0.25 * h); };
      const ShellSamples samples = sample_shell(surface, band, phi, o);
      const TriangleMesh mesh = shell_mesh(samples, 0.0);
      const MeshTopology topology = analyze_topology(mesh);
      expect_printable(topology);
      EXPECT_EQ((solid_ref.euler_characteristic - topology.euler_characteristic) / 2, 9);
      EXPECT_EQ(spot_statistics(band, phi, 0.0).count, 9);
      // Below the sheet for inside (against the normal), above it for outside.
      const double lo = offset == WallOffset::inside    ? 0.5 - t
                        : offset == WallOffset::outside ? 0.5
                                                        : 0.5 - t / 2;
      double worst = 0.0;
      int rays = 0;
      while (rays < 40) {
        const Vec3 p(uniform(rng), uniform(rng), 0.0);
        if (sheet_pattern(p + Vec3(0, 0, 0.5)) > -0.99) continue;  // away from pores
        const std::vector<double> hits = ray_hits(mesh, p, Vec3::UnitZ());
        ASSERT_EQ(hits.size(), 2u);
        worst = std::max(worst, std::abs((hits[1] - hits[0]) - t) / t);
        EXPECT_NEAR(hits[0], lo, 0.05 * t) << to_string(offset);
        ++rays;
      }
      std::printf("open sheet, wall %.1f h %-8s: worst thickness error %.2f%%\n", t / h,
                  to_string(offset).c_str(), 100 * worst);
      EXPECT_LT(worst, 0.10);
    }
}

// A closed torus (R = 0.3, r = 0.1 around kCenter, axis z) from the isosurface of its distance.
TriangleMesh closed_torus() {
  const Grid grid = unit_grid();
  std::vector<Coord> points;
  std::vector<double> values;
  for (int k = 0; k < kN; ++k)
    for (int j = 0; j < kN; ++j)
      for (int i = 0; i < kN; ++i) {
        const Vec3 p = grid.position({i, j, k}) - kCenter;
        const double d = std::hypot(std::hypot(p.x(), p.y()) - 0.3, p.z()) - 0.1;
        if (d > 0.05) continue;
        points.push_back({i, j, k});
        values.push_back(d);
      }
  return extract_isosurface({&grid, points, values, 1.0}, 0.0);
}

TEST(WindingNumber, ClosedMeshInsideIsOneOutsideZero) {
  const TriangleMesh torus = closed_torus();
  const WindingNumber w(torus);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  double worst_fast = 0.0;
  for (int n = 0; n < 400; ++n) {
    const Vec3 p(uniform(rng), uniform(rng), uniform(rng));
    const Vec3 q = p - kCenter;
    const double d = std::hypot(std::hypot(q.x(), q.y()) - 0.3, q.z()) - 0.1;
    if (std::abs(d) < 0.01) continue;  // the mesh is the distance's isosurface to about h^2
    const double exact = w.exact(p), fast = w(p);
    EXPECT_NEAR(exact, d < 0 ? 1.0 : 0.0, 1e-6) << "d " << d;
    worst_fast = std::max(worst_fast, std::abs(fast - exact));
  }
  std::printf("torus (%zu triangles): worst |fast - exact| = %.2e\n", w.triangle_count(), worst_fast);
  EXPECT_LT(worst_fast, 0.05);
  EXPECT_NEAR(w(kCenter), 0.0, 1e-2);  // the hole of the torus
}

TEST(WindingNumber, OpenSheetJumpsByOneAcrossIt) {
  const TriangleMesh sheet = square_sheet(12);
  const WindingNumber w(sheet);
  // The jump is the sheet's solid angle seen from both sides: 1 close to it, less farther away.
  for (double z : {0.001, 0.01, 0.05, 0.2}) {
    const Vec3 above(0.45, 0.55, 0.5 + z), below(0.45, 0.55, 0.5 - z);
    if (z <= 0.01) {
      EXPECT_NEAR(w.exact(below) - w.exact(above), 1.0, 0.05) << z;
    }
    EXPECT_NEAR(w(below) - w(above), w.exact(below) - w.exact(above), 0.05) << z;
    EXPECT_GT(side_of_surface(w, above, Vec3(0.45, 0.55, 0.5), 0.01), 0.9) << z;
    EXPECT_LT(side_of_surface(w, below, Vec3(0.45, 0.55, 0.5), 0.01), -0.9) << z;
  }
}

#ifdef PORESHELL_DATA_DIR
// The bunny scan has holes in its base: points just off its faces (well away from the holes' rims)
// must still be classified, by the winding number itself and by the side test the shell uses.
TEST(WindingNumber, BunnyWithHolesInsideAndOutside) {
  const TriangleMesh bunny = read_triangle_mesh(std::string(PORESHELL_DATA_DIR) + "/stanford-bunny.obj");
  const MeshSurface surface(bunny);
  const WindingNumber w(bunny);
  // Boundary vertices (on the holes' rims).
  std::vector<Vec3> rim;
  {
    std::vector<std::pair<std::uint64_t, int>> edges;
    for (const auto& t : bunny.triangles)
      for (int e = 0; e < 3; ++e) {
        const auto a = static_cast<std::uint64_t>(std::min(t[e], t[(e + 1) % 3]));
        const auto b = static_cast<std::uint64_t>(std::max(t[e], t[(e + 1) % 3]));
        edges.push_back({(a << 32) | b, 0});
      }
    std::sort(edges.begin(), edges.end());
    for (std::size_t i = 0; i < edges.size(); ++i) {
      const bool single = (i == 0 || edges[i - 1].first != edges[i].first) &&
                          (i + 1 == edges.size() || edges[i + 1].first != edges[i].first);
      if (single) rim.push_back(bunny.vertices[edges[i].first >> 32]);
    }
  }
  ASSERT_FALSE(rim.empty());
  Box box{bunny.vertices.front(), bunny.vertices.front()};
  for (const Vec3& v : bunny.vertices) {
    box.min = box.min.cwiseMin(v);
    box.max = box.max.cwiseMax(v);
  }
  const double size = (box.max - box.min).maxCoeff();
  const double offset = 0.01 * size;

  int tested = 0, winding_right = 0, side_right = 0;
  double seconds = 0.0;
  for (std::size_t f = 0; f < bunny.triangles.size() && tested < 300; f += 97) {
    const auto& t = bunny.triangles[f];
    const Vec3 c = (bunny.vertices[t[0]] + bunny.vertices[t[1]] + bunny.vertices[t[2]]) / 3.0;
    const Vec3 n = (bunny.vertices[t[1]] - bunny.vertices[t[0]])
                       .cross(bunny.vertices[t[2]] - bunny.vertices[t[0]])
                       .normalized();
    double to_rim = INFINITY;
    for (const Vec3& r : rim) to_rim = std::min(to_rim, (r - c).norm());
    if (to_rim < 10 * offset) continue;
    for (double sign : {-1.0, 1.0}) {
      const Vec3 p = c + sign * offset * n;
      if (surface.distance(p) < 0.9 * offset) continue;  // a thin part: another face is closer
      const auto start = std::chrono::steady_clock::now();
      const double wp = w(p);
      const double side = side_of_surface(w, p, *surface.closest_point(p), 0.25 * offset);
      seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      ++tested;
      winding_right += (wp > 0.5) == (sign < 0);
      side_right += (side > 0) == (sign > 0);
    }
  }
  std::printf(
      "bunny (%zu triangles, %zu rim vertices): %d points, winding right %d, side right %d, "
      "%.1f us per side test (3 winding numbers)\n",
      w.triangle_count(), rim.size(), tested, winding_right, side_right, 1e6 * seconds / tested);
  EXPECT_GT(tested, 200);
  EXPECT_EQ(winding_right, tested);
  EXPECT_EQ(side_right, tested);
  // Far outside the box, and the fast sum against the exact one at a few points.
  EXPECT_NEAR(w(box.max + Vec3::Constant(size)), 0.0, 1e-3);
  for (int i = 0; i < 5; ++i) {
    const Vec3 p = box.min + (box.max - box.min) * (0.2 + 0.15 * i);
    EXPECT_NEAR(w(p), w.exact(p), 0.05);
  }
}
#endif

}  // namespace
}  // namespace poreshell
