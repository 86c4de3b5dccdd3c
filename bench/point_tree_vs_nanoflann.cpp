// PointTree (geometry/point_tree.*) against nanoflann's k-d tree, both in this process: build, nearest
// and k nearest on the bunny's points and on 2.7 M random points, one thread, the queries the code makes
// (nearest: lattice points near the cloud; k nearest: 9 for the umbrellas, 10 for the splats' normals).
// Usage: bench_point_tree_vs_nanoflann [queries] [points.xyz]
//   (defaults: 200,000 queries of each kind, data/stanford-bunny-points.xyz)
// Figures and the conclusion: docs/benchmarks.md, "PointTree against nanoflann".

#include <fmt/core.h>

#include <chrono>
#include <cstdint>
#include <cstdio>
#include <nanoflann.hpp>
#include <random>
#include <string>
#include <vector>

#include "geometry/point_tree.hpp"
#include "io/point_io.hpp"

namespace {

using poreshell::Vec3;
using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

struct Cloud {
  const std::vector<Vec3>& points;
  std::size_t kdtree_get_point_count() const { return points.size(); }
  double kdtree_get_pt(std::size_t i, std::size_t d) const { return points[i][static_cast<Eigen::Index>(d)]; }
  template <class Box>
  bool kdtree_get_bbox(Box&) const {
    return false;
  }
};
using Flann =
    nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, Cloud>, Cloud, 3, std::uint32_t>;

struct Times {
  double build = 0, nearest = 0, knn9 = 0, knn10 = 0;
  double checksum = 0;  // sum of nearest distances: the two must agree
};

void report(const std::string& name, std::size_t n, std::size_t queries, const Times& ours,
            const Times& theirs) {
  fmt::print("{}: {} points, {} queries (one thread)\n", name, n, queries);
  fmt::print("  {:<12}{:>12}{:>12}{:>10}\n", "", "PointTree", "nanoflann", "ratio");
  const auto row = [](const char* what, double a, double b) {
    fmt::print("  {:<12}{:>10.3f} s{:>10.3f} s{:>10.2f}\n", what, a, b, a / b);
  };
  row("build", ours.build, theirs.build);
  row("nearest", ours.nearest, theirs.nearest);
  row("9 nearest", ours.knn9, theirs.knn9);
  row("10 nearest", ours.knn10, theirs.knn10);
  fmt::print("  nearest-distance sums: {:.12g} vs {:.12g}\n", ours.checksum, theirs.checksum);
  std::fflush(stdout);
}

void compare(const std::string& name, const std::vector<Vec3>& points, const std::vector<Vec3>& queries) {
  Times ours, theirs;
  {
    auto t0 = Clock::now();
    const poreshell::PointTree tree(points);
    ours.build = seconds_since(t0);
    t0 = Clock::now();
    for (const Vec3& q : queries) ours.checksum += tree.nearest(q).second;
    ours.nearest = seconds_since(t0);
    std::size_t sink = 0;
    t0 = Clock::now();
    for (const Vec3& q : queries) sink += tree.k_nearest(q, 9).back();
    ours.knn9 = seconds_since(t0);
    t0 = Clock::now();
    for (const Vec3& q : queries) sink += tree.k_nearest(q, 10).back();
    ours.knn10 = seconds_since(t0);
    if (sink == 1) fmt::print(" ");
  }
  {
    const Cloud cloud{points};
    auto t0 = Clock::now();
    Flann tree(3, cloud, nanoflann::KDTreeSingleIndexAdaptorParams(10));  // builds
    theirs.build = seconds_since(t0);
    std::uint32_t index[10];
    double d2[10];
    t0 = Clock::now();
    for (const Vec3& q : queries) {
      tree.knnSearch(q.data(), 1, index, d2);
      theirs.checksum += std::sqrt(d2[0]);
    }
    theirs.nearest = seconds_since(t0);
    std::size_t sink = 0;
    t0 = Clock::now();
    for (const Vec3& q : queries) sink += index[tree.knnSearch(q.data(), 9, index, d2) - 1];
    theirs.knn9 = seconds_since(t0);
    t0 = Clock::now();
    for (const Vec3& q : queries) sink += index[tree.knnSearch(q.data(), 10, index, d2) - 1];
    theirs.knn10 = seconds_since(t0);
    if (sink == 1) fmt::print(" ");
  }
  report(name, points.size(), queries.size(), ours, theirs);
}

// Queries near the cloud, as the code asks: each point moved by up to `jitter` per axis.
std::vector<Vec3> near_queries(const std::vector<Vec3>& points, std::size_t count, double jitter,
                               std::mt19937_64& rng) {
  std::uniform_int_distribution<std::size_t> pick(0, points.size() - 1);
  std::uniform_real_distribution<double> off(-jitter, jitter);
  std::vector<Vec3> q(count);
  for (Vec3& x : q) x = points[pick(rng)] + Vec3(off(rng), off(rng), off(rng));
  return q;
}

}  // namespace

int main(int argc, char** argv) {
  const std::size_t queries = argc > 1 ? std::stoul(argv[1]) : 200'000;
  const std::string path =
      argc > 2 ? argv[2] : std::string(PORESHELL_DATA_DIR) + "/stanford-bunny-points.xyz";
  std::mt19937_64 rng(17);
  const std::vector<Vec3> bunny = poreshell::read_point_cloud(path).points;
  compare("bunny", bunny, near_queries(bunny, queries, 0.005, rng));

  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<Vec3> random(2'700'000);
  for (Vec3& p : random) p = Vec3(unit(rng), unit(rng), unit(rng));
  compare("random", random, near_queries(random, queries, 0.005, rng));
  return 0;
}
