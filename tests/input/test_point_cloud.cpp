#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include "band/band.hpp"
#include "core/error.hpp"
#include "geometry/mesh_surface.hpp"
#include "input/point_cloud.hpp"
#include "input/point_segmentation.hpp"
#include "io/mesh_io.hpp"
#include "io/point_io.hpp"
#include "test_support.hpp"

using namespace poreshell;
namespace fs = std::filesystem;

namespace {

std::string binary_ply(const std::vector<Vec3>& points, std::size_t declared) {
  std::string s = "ply\nformat binary_little_endian 1.0\nelement vertex " + std::to_string(declared) +
                  "\nproperty float x\nproperty float y\nproperty float z\nend_header\n";
  for (const Vec3& p : points)
    for (int a = 0; a < 3; ++a) {
      const auto f = static_cast<float>(p[a]);
      s.append(reinterpret_cast<const char*>(&f), sizeof f);
    }
  return s;
}

// Points on the unit sphere (Fibonacci spiral): nearly uniform, deterministic.
std::vector<Vec3> sphere_points(std::size_t n, const Vec3& center, double radius) {
  std::vector<Vec3> out;
  const double golden = M_PI * (3.0 - std::sqrt(5.0));
  for (std::size_t i = 0; i < n; ++i) {
    const double z = 1.0 - 2.0 * (static_cast<double>(i) + 0.5) / static_cast<double>(n);
    const double r = std::sqrt(1.0 - z * z), t = golden * static_cast<double>(i);
    out.push_back(center + radius * Vec3(r * std::cos(t), r * std::sin(t), z));
  }
  return out;
}

}  // namespace

// ---------- readers ----------

TEST(PointReaders, XyzWithCommentsAndExtraColumns) {
  TempDir dir;
  const auto p = dir.file("a.xyz", "# a comment\n0 0 0\n\n1.5 2 3 0 0 1\n  -1e-3\t4 5 # trailing\n");
  const PointCloud c = read_point_cloud(p);
  ASSERT_EQ(c.points.size(), 3u);
  EXPECT_EQ(c.points[1], Vec3(1.5, 2, 3));
  EXPECT_EQ(c.points[2], Vec3(-1e-3, 4, 5));
  EXPECT_TRUE(c.triangles.empty());
}

TEST(PointReaders, PlyAsciiBinaryAndWithFaces) {
  TempDir dir;
  const std::vector<Vec3> pts{{0, 0, 0}, {1, 0, 0}, {0, 1, 2}, {3, 4, 5}};
  const auto ascii = dir.file("a.ply",
                              "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
                              "property float z\nproperty float nx\nproperty float ny\nproperty float nz\n"
                              "end_header\n0 0 0 0 0 1\n1 0 0 0 0 1\n0 1 2 0 0 1\n3 4 5 0 0 1\n");
  const auto binary = dir.file("b.ply", binary_ply(pts, pts.size()));
  const auto faces = dir.file("c.ply",
                              "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
                              "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
                              "end_header\n0 0 0\n1 0 0\n0 1 2\n3 4 5\n4 0 1 2 3\n");
  for (const auto& f : {ascii, binary, faces}) {
    const PointCloud c = read_point_cloud(f);
    ASSERT_EQ(c.points.size(), 4u) << f;
    for (std::size_t i = 0; i < 4; ++i) EXPECT_EQ(c.points[i], pts[i]) << f;
  }
  EXPECT_EQ(read_point_cloud(faces).triangles.size(), 2u);  // the quad as a fan
}

TEST(PointReaders, BadInputsEachHaveTheirOwnMessage) {
  TempDir dir;
  const std::vector<std::pair<fs::path, std::string>> cases{
      {dir.file("missing-never-written.xyz", "") / "x.xyz", "does not exist"},
      {dir.file("empty.xyz", ""), "is empty"},
      {dir.file("comments.xyz", "# only a comment\n\n"), "holds no points"},
      {dir.file("nan.xyz", "0 0 0\n1 nan 0\n"), "point 2 has a NaN"},
      {dir.file("inf.xyz", "0 0 0\n1 2 inf\n"), "point 2 has a NaN or infinite"},
      {dir.file("short.xyz", "0 0 0\n1 2\n"), "line 2: expected three numbers"},
      {dir.file("words.xyz", "hello world\n"), "line 1: expected three numbers"},
      {dir.file("truncated.ply", binary_ply({{0, 0, 0}, {1, 0, 0}}, 4)), "truncated"},
      {dir.file("truncated-ascii.ply",
                "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                "property float z\nend_header\n0 0 0\n"),
       "truncated"},
      {dir.file("nan.ply",
                "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\n"
                "property float z\nend_header\n0 0 nan\n1 0 0\n"),
       "point 1 has a NaN"},
      {dir.file("novertex.ply", "ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nend_header\n"),
       "has no vertices"},
      {dir.file("garbage.ply", "this is not a ply file at all\n"), "PLY"},
      {dir.file("cloud.las", "0 0 0\n"), "unknown point file extension"},
  };
  for (const auto& c : cases) {
    const std::string msg = input_error([&] { read_point_cloud(c.first); });
    EXPECT_NE(msg.find(c.second), std::string::npos) << c.first << ": '" << msg << "'";
  }
}

// ---------- the direct route ----------

TEST(PointTree, NearestAndKNearestMatchBruteForce) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<Vec3> pts(2000);
  for (auto& p : pts) p = Vec3(u(rng), u(rng), u(rng));
  const PointTree tree(pts);
  for (int q = 0; q < 200; ++q) {
    const Vec3 x(1.5 * u(rng), 1.5 * u(rng), 1.5 * u(rng));
    std::vector<std::pair<double, std::size_t>> all;
    for (std::size_t i = 0; i < pts.size(); ++i) all.push_back({(pts[i] - x).norm(), i});
    std::sort(all.begin(), all.end());
    const auto [i, d] = tree.nearest(x);
    EXPECT_EQ(i, all[0].second);
    EXPECT_EQ(d, all[0].first);
    const auto k = tree.k_nearest(x, 9);
    ASSERT_EQ(k.size(), 9u);
    for (std::size_t j = 0; j < 9; ++j) EXPECT_EQ(k[j], all[j].second);
  }
}

// Trees of more than 2^16 points build their subtrees in parallel: the same answers as brute force
// (ties to the lower index) with one thread and with several. A lattice with repeated points makes
// ties in the median splits and in the distances.
TEST(PointTree, ParallelBuildMatchesBruteForceWithTies) {
  std::vector<Vec3> pts;
  for (int k = 0; k < 40; ++k)
    for (int j = 0; j < 40; ++j)
      for (int i = 0; i < 50; ++i) pts.emplace_back(0.1 * i, 0.1 * j, 0.1 * k);
  pts.insert(pts.end(), pts.begin(), pts.begin() + 20000);  // exact duplicates, higher indices
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-0.5, 5.5);
  std::vector<Vec3> queries(60);
  for (auto& x : queries) x = Vec3(u(rng), 0.8 * u(rng), 0.8 * u(rng));
  queries.push_back(Vec3(0.05, 0.05, 0.05));  // (nearly) equidistant from 8 lattice points
  for (int threads : {1, 2}) {
    const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    const PointTree tree(pts);
    for (const Vec3& x : queries) {
      std::size_t best = 0;
      for (std::size_t i = 1; i < pts.size(); ++i)
        if ((pts[i] - x).squaredNorm() < (pts[best] - x).squaredNorm()) best = i;
      const auto [i, d] = tree.nearest(x);
      EXPECT_EQ(i, best) << threads << " threads";
      EXPECT_DOUBLE_EQ(d, (pts[best] - x).norm());
    }
  }
}

// Properties of the splat distance against brute force over all splats: the same minimum, a closest
// point at that distance, 1-Lipschitz, and close to the true distance of the sampled sphere.
TEST(SplatSurface, DistanceMatchesBruteForceAndIsLipschitz) {
  const Vec3 c(0.1, -0.2, 0.3);
  const double r = 0.5;
  const std::vector<Vec3> pts = sphere_points(3000, c, r);
  const SplatSurface s(pts);
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  double worst_sphere_error = 0.0;
  for (int q = 0; q < 300; ++q) {
    const Vec3 x = c + Vec3(u(rng), u(rng), u(rng));
    double brute = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < pts.size(); ++i) {  // distance to disc i, written out independently
      const Vec3 d = x - pts[i];
      const double a = d.dot(s.normal(i));
      const double t = (d - a * s.normal(i)).norm();
      brute = std::min(brute, std::hypot(a, std::max(0.0, t - s.radius(i))));
    }
    const double got = s.distance(x);
    EXPECT_NEAR(got, brute, 1e-12);
    const Vec3 cp = *s.closest_point(x);
    EXPECT_NEAR((cp - x).norm(), got, 1e-12);
    const Vec3 y = x + 0.05 * Vec3(u(rng), u(rng), u(rng));
    EXPECT_LE(std::abs(s.distance(y) - got), (y - x).norm() + 1e-12);
    worst_sphere_error = std::max(worst_sphere_error, std::abs(got - std::abs((x - c).norm() - r)));
  }
  // Discs lie off the sphere by their sagitta r^2 / (2R), and leave small gaps between them: both a
  // small fraction of the sample spacing.
  const double spacing = std::sqrt(4.0 * M_PI * r * r / static_cast<double>(pts.size()));
  EXPECT_LT(worst_sphere_error, 0.1 * spacing);
}

// ---------- the bunny: point-cloud routes against the mesh route ----------

namespace {

// The bunny's mesh and its vertex file, both placed in the paper's frame the way the pipeline places
// the mesh (longest side 1 with 4 cells of padding), on the grid with n points along the longest side.
struct BunnyCase {
  Grid grid{Vec3::Zero(), 1.0, {3, 3, 3}};  // replaced by the fitted grid
  TriangleMesh mesh;
  std::vector<Vec3> points;
};

BunnyCase bunny_case(int n) {
  BunnyCase b;
  b.mesh = read_triangle_mesh(fs::path(PORESHELL_DATA_DIR) / "stanford-bunny.obj");
  b.points = read_point_cloud(fs::path(PORESHELL_DATA_DIR) / "stanford-bunny-points.xyz").points;
  Box box{b.mesh.vertices.front(), b.mesh.vertices.front()};
  for (const Vec3& v : b.mesh.vertices) {
    box.min = box.min.cwiseMin(v);
    box.max = box.max.cwiseMax(v);
  }
  const double h = 1.0 / (n - 1), pad = 4 * h;
  const double scale = (1.0 - 2 * pad) / (box.max - box.min).maxCoeff();
  const Vec3 center = 0.5 * (box.min + box.max);
  for (Vec3& v : b.mesh.vertices) v = (v - center) * scale + Vec3::Constant(0.5);
  for (Vec3& v : b.points) v = (v - center) * scale + Vec3::Constant(0.5);
  const Vec3 half = 0.5 * scale * (box.max - box.min) + Vec3::Constant(pad);
  b.grid = Grid::fitted(Box{Vec3::Constant(0.5) - half, Vec3::Constant(0.5) + half}, n);
  return b;
}

struct Agreement {
  double share_of_mesh_band = 0.0;   // mesh-route band voxels that the other band has too
  double share_of_other_band = 0.0;  // the other band's voxels that the mesh band has too
  double max_error_h = 0.0;          // max | |d_other| - d_mesh | / h over common band voxels
  double mean_error_h = 0.0;
  std::size_t mesh_voxels = 0, other_voxels = 0;
};

Agreement compare_bands(const NarrowBand& mesh, const NarrowBand& other) {
  Agreement a;
  a.mesh_voxels = mesh.size();
  a.other_voxels = other.size();
  std::size_t common = 0;
  for (std::size_t v = 0; v < other.size(); ++v) {
    const std::int64_t m = mesh.find(other.voxels()[v]);
    if (m < 0) continue;
    ++common;
    const double e = std::abs(std::abs(other.distance()[v]) - mesh.distance()[static_cast<std::size_t>(m)]) /
                     mesh.grid().h();
    a.max_error_h = std::max(a.max_error_h, e);
    a.mean_error_h += e;
  }
  a.mean_error_h /= static_cast<double>(std::max<std::size_t>(common, 1));
  a.share_of_mesh_band = static_cast<double>(common) / static_cast<double>(mesh.size());
  a.share_of_other_band = static_cast<double>(common) / static_cast<double>(other.size());
  return a;
}

void print(const char* route, int n, const Agreement& a, double seconds_surface, double seconds_band) {
  std::printf(
      "bunny N=%d %-7s band %zu voxels (mesh %zu): %.4f of the mesh band shared, %.4f of its own; "
      "| |d| - d_mesh | max %.3f h, mean %.4f h; surface %.2f s, band %.2f s\n",
      n, route, a.other_voxels, a.mesh_voxels, a.share_of_mesh_band, a.share_of_other_band, a.max_error_h,
      a.mean_error_h, seconds_surface, seconds_band);
}

double seconds_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

struct Bounds {
  double min_share, max_error_h, max_mean_error_h;
};

void expect_within(const Agreement& a, const Bounds& b) {
  EXPECT_GT(a.share_of_mesh_band, b.min_share);
  EXPECT_GT(a.share_of_other_band, b.min_share);
  EXPECT_LT(a.max_error_h, b.max_error_h);
  EXPECT_LT(a.mean_error_h, b.max_mean_error_h);
}

void bunny_agreement(int n, const Bounds& direct_bounds, const Bounds& paper_bounds) {
  const BunnyCase b = bunny_case(n);
  auto t = std::chrono::steady_clock::now();
  const MeshSurface mesh_surface(b.mesh);
  const double mesh_surface_s = seconds_since(t);
  t = std::chrono::steady_clock::now();
  const NarrowBand mesh_band = build_band(mesh_surface, b.grid);
  print("mesh", n, compare_bands(mesh_band, mesh_band), mesh_surface_s, seconds_since(t));

  t = std::chrono::steady_clock::now();
  const SplatSurface splats(b.points);
  const double splat_s = seconds_since(t);
  t = std::chrono::steady_clock::now();
  const NarrowBand direct_band = build_band(splats, b.grid);
  const Agreement direct = compare_bands(mesh_band, direct_band);
  print("direct", n, direct, splat_s, seconds_since(t));
  expect_within(direct, direct_bounds);

  t = std::chrono::steady_clock::now();
  SegmentationStats stats;
  const auto level_set = segment_point_cloud(b.points, {}, b.grid, {}, &stats);
  const double segment_s = seconds_since(t);
  t = std::chrono::steady_clock::now();
  const NarrowBand paper_band = build_band(*level_set, b.grid);
  const Agreement paper = compare_bands(mesh_band, paper_band);
  print("paper", n, paper, segment_s, seconds_since(t));
  std::printf(
      "  paper route: %lld points after densification, %lld band + %lld ghost voxels (%lld inside), "
      "%d steps (last change %.2e), dt %.3g, eps %.3g, lambda %.3g, zero level %lld triangles, "
      "max gap to the points %.3f h\n",
      static_cast<long long>(stats.points), static_cast<long long>(stats.band_voxels),
      static_cast<long long>(stats.ghost_voxels), static_cast<long long>(stats.inside_voxels),
      stats.iterations, stats.last_change, stats.dt, stats.epsilon, stats.lambda,
      static_cast<long long>(stats.zero_level_triangles), stats.zero_level_max_gap / b.grid.h());
  expect_within(paper, paper_bounds);
}

}  // namespace

// Bounds a little above the measured figures (docs/point-clouds.md). The largest errors sit at the
// rims of the base's holes: discs reach past a rim, the paper route caps the holes.
TEST(BunnyPoints, BothRoutesGiveTheMeshRoutesBand) {
  bunny_agreement(65, {0.95, 1.0, 0.06}, {0.94, 2.0, 0.1});
}

// The paper's grid (N = 131): the figures of docs/point-clouds.md. Run with
//   test_point_cloud --gtest_also_run_disabled_tests --gtest_filter='*PaperGrid*'
TEST(BunnyPoints, DISABLED_PaperGrid) {
  bunny_agreement(131, {0.95, 1.7, 0.07}, {0.96, 2.0, 0.07});
}
