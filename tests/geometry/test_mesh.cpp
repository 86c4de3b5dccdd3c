// Topology checks on hand-built meshes, the binary STL round trip and atomic file writing.

#include <gtest/gtest.h>
#include <tbb/global_control.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <numbers>
#include <stdexcept>

#include "core/error.hpp"
#include "geometry/mesh.hpp"
#include "io/atomic_file.hpp"
#include "io/stl.hpp"

namespace poreshell {
namespace {
namespace fs = std::filesystem;

// Builds meshes from positions, welding equal positions so shapes can share vertices.
class MeshBuilder {
 public:
  std::int32_t vertex(const Vec3& p) {
    const auto key = std::array<double, 3>{p.x(), p.y(), p.z()};
    const auto [it, added] = index_.try_emplace(key, static_cast<std::int32_t>(mesh.vertices.size()));
    if (added) mesh.vertices.push_back(p);
    return it->second;
  }
  void triangle(const Vec3& a, const Vec3& b, const Vec3& c) {
    mesh.triangles.push_back({vertex(a), vertex(b), vertex(c)});
  }
  void quad(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
    triangle(a, b, c);
    triangle(a, c, d);
  }
  // Axis-aligned box, outward oriented. Corner n has bits (x, y, z) = (n & 1, n & 2, n & 4).
  void box(const Vec3& lo, const Vec3& hi) {
    auto c = [&](int n) {
      return Vec3(n & 1 ? hi.x() : lo.x(), n & 2 ? hi.y() : lo.y(), n & 4 ? hi.z() : lo.z());
    };
    const int faces[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4},
                             {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
    for (const auto& f : faces) quad(c(f[0]), c(f[1]), c(f[2]), c(f[3]));
  }
  void tetrahedron(const Vec3& o, double s) {
    const Vec3 a = o, b = o + Vec3(s, 0, 0), c = o + Vec3(0, s, 0), d = o + Vec3(0, 0, s);
    triangle(a, c, b);
    triangle(a, b, d);
    triangle(a, d, c);
    triangle(b, c, d);
  }
  TriangleMesh mesh;

 private:
  std::map<std::array<double, 3>, std::int32_t> index_;
};

void expect_closed_manifold(const MeshTopology& t) {
  EXPECT_TRUE(t.closed());
  EXPECT_TRUE(t.manifold());
  EXPECT_TRUE(t.oriented());
  EXPECT_EQ(t.degenerate_triangles, 0);
}

TEST(MeshTopology, TetrahedronIsClosedSphereWithPositiveVolume) {
  MeshBuilder b;
  b.tetrahedron(Vec3(1, 2, 3), 1.0);
  const MeshTopology t = analyze_topology(b.mesh);
  expect_closed_manifold(t);
  EXPECT_EQ(t.vertices, 4);
  EXPECT_EQ(t.edges, 6);
  EXPECT_EQ(t.triangles, 4);
  EXPECT_EQ(t.euler_characteristic, 2);
  EXPECT_EQ(t.components, 1);
  EXPECT_NEAR(t.signed_volume, 1.0 / 6.0, 1e-12);
}

TEST(MeshTopology, CubeHasEulerTwoAndItsVolume) {
  MeshBuilder b;
  b.box(Vec3(-1, 0, 2), Vec3(1, 3, 6));
  const MeshTopology t = analyze_topology(b.mesh);
  expect_closed_manifold(t);
  EXPECT_EQ(t.vertices, 8);
  EXPECT_EQ(t.edges, 18);
  EXPECT_EQ(t.euler_characteristic, 2);
  EXPECT_NEAR(t.signed_volume, 24.0, 1e-12);
}

TEST(MeshTopology, FlippedCubeHasNegativeVolume) {
  MeshBuilder b;
  b.box(Vec3(0, 0, 0), Vec3(2, 2, 2));
  for (auto& tri : b.mesh.triangles) std::swap(tri[1], tri[2]);
  const MeshTopology t = analyze_topology(b.mesh);
  expect_closed_manifold(t);  // consistently flipped is still consistently oriented
  EXPECT_NEAR(t.signed_volume, -8.0, 1e-12);
}

TEST(MeshTopology, OneFlippedTriangleIsMisoriented) {
  MeshBuilder b;
  b.tetrahedron(Vec3(0, 0, 0), 1.0);
  std::swap(b.mesh.triangles[3][1], b.mesh.triangles[3][2]);
  const MeshTopology t = analyze_topology(b.mesh);
  EXPECT_TRUE(t.closed());
  EXPECT_EQ(t.misoriented_edges, 3);
}

TEST(MeshTopology, OpenCubeHasBoundaryEdges) {
  MeshBuilder b;
  b.box(Vec3(0, 0, 0), Vec3(1, 1, 1));
  b.mesh.triangles.resize(10);  // drop the +z face
  const MeshTopology t = analyze_topology(b.mesh);
  EXPECT_FALSE(t.closed());
  EXPECT_EQ(t.boundary_edges, 4);
  EXPECT_TRUE(t.manifold());
  EXPECT_EQ(t.euler_characteristic, 1);  // a disc
}

TEST(MeshTopology, CubesSharingAnEdgeAreNonManifold) {
  MeshBuilder b;
  b.box(Vec3(0, 0, 0), Vec3(1, 1, 1));
  b.box(Vec3(1, 1, 0), Vec3(2, 2, 1));
  const MeshTopology t = analyze_topology(b.mesh);
  EXPECT_TRUE(t.closed());
  EXPECT_EQ(t.nonmanifold_edges, 1);
  EXPECT_FALSE(t.manifold());
  EXPECT_EQ(t.components, 1);  // joined through the shared edge
}

TEST(MeshTopology, TetrahedraSharingAVertexAreNonManifold) {
  MeshBuilder b;
  b.tetrahedron(Vec3(0, 0, 0), 1.0);
  b.tetrahedron(Vec3(1, 0, 0), 1.0);  // its first corner is the first one's (1, 0, 0)
  const MeshTopology t = analyze_topology(b.mesh);
  EXPECT_TRUE(t.closed());
  EXPECT_EQ(t.nonmanifold_edges, 0);
  EXPECT_EQ(t.nonmanifold_vertices, 1);
  EXPECT_FALSE(t.manifold());
  EXPECT_EQ(t.vertices, 7);
  EXPECT_EQ(t.components, 2);
  EXPECT_EQ(t.euler_characteristic, 3);
}

TEST(MeshTopology, TorusHasEulerZero) {
  const double big = 3.0, small = 1.0;
  const int nu = 24, nv = 12;
  auto p = [&](int i, int j) {
    const double u = 2 * std::numbers::pi * (i % nu) / nu, v = 2 * std::numbers::pi * (j % nv) / nv;
    return Vec3((big + small * std::cos(v)) * std::cos(u), (big + small * std::cos(v)) * std::sin(u),
                small * std::sin(v));
  };
  MeshBuilder b;
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j) b.quad(p(i, j), p(i + 1, j), p(i + 1, j + 1), p(i, j + 1));
  const MeshTopology t = analyze_topology(b.mesh);
  expect_closed_manifold(t);
  EXPECT_EQ(t.components, 1);
  EXPECT_EQ(t.euler_characteristic, 0);
  const double exact = 2 * std::numbers::pi * std::numbers::pi * big * small * small;
  EXPECT_GT(t.signed_volume, 0.9 * exact);
  EXPECT_LT(t.signed_volume, exact);
}

// The counts are found at the vertices, by tasks that share the components' union-find: the same for any
// order of the triangles, any numbering of the vertices and any thread count, defects included (a torus, a
// flipped triangle, an open face, two boxes on an edge, a second component).
TEST(MeshTopology, CountsDoNotDependOnOrderNumberingOrThreads) {
  MeshBuilder b;
  const int nu = 24, nv = 12;
  auto p = [&](int i, int j) {
    const double u = 2 * std::numbers::pi * (i % nu) / nu, v = 2 * std::numbers::pi * (j % nv) / nv;
    return Vec3((3 + std::cos(v)) * std::cos(u), (3 + std::cos(v)) * std::sin(u), std::sin(v));
  };
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j) b.quad(p(i, j), p(i + 1, j), p(i + 1, j + 1), p(i, j + 1));
  std::swap(b.mesh.triangles[7][1], b.mesh.triangles[7][2]);
  b.box(Vec3(10, 0, 0), Vec3(11, 1, 1));
  b.box(Vec3(11, 1, 0), Vec3(12, 2, 1));
  b.mesh.triangles.pop_back();
  b.tetrahedron(Vec3(20, 0, 0), 1.0);
  const MeshTopology whole = analyze_topology(b.mesh);
  EXPECT_EQ(whole.misoriented_edges, 3);
  EXPECT_EQ(whole.nonmanifold_edges, 1);
  EXPECT_GT(whole.boundary_edges, 0);
  EXPECT_EQ(whole.components, 3);

  TriangleMesh shuffled;  // triangles reversed, vertices numbered backwards
  const auto vertex_count = static_cast<std::int32_t>(b.mesh.vertices.size());
  shuffled.vertices.assign(b.mesh.vertices.rbegin(), b.mesh.vertices.rend());
  for (auto it = b.mesh.triangles.rbegin(); it != b.mesh.triangles.rend(); ++it)
    shuffled.triangles.push_back(
        {vertex_count - 1 - (*it)[0], vertex_count - 1 - (*it)[1], vertex_count - 1 - (*it)[2]});
  for (int threads : {1, 2, 4}) {
    const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    for (const TriangleMesh* m : {&b.mesh, &shuffled}) {
      const MeshTopology t = analyze_topology(*m);
      EXPECT_EQ(t.vertices, whole.vertices) << threads;
      EXPECT_EQ(t.edges, whole.edges) << threads;
      EXPECT_EQ(t.boundary_edges, whole.boundary_edges) << threads;
      EXPECT_EQ(t.nonmanifold_edges, whole.nonmanifold_edges) << threads;
      EXPECT_EQ(t.misoriented_edges, whole.misoriented_edges) << threads;
      EXPECT_EQ(t.nonmanifold_vertices, whole.nonmanifold_vertices) << threads;
      EXPECT_EQ(t.components, whole.components) << threads;
      EXPECT_EQ(t.euler_characteristic, whole.euler_characteristic) << threads;
      // The same sum in the same order (an open mesh's volume depends on the reference point).
      if (m == &b.mesh) {
        EXPECT_EQ(t.signed_volume, whole.signed_volume) << threads;
      }
    }
  }
}

TEST(MeshTopology, DegenerateTrianglesAreCounted) {
  MeshBuilder b;
  b.tetrahedron(Vec3(0, 0, 0), 1.0);
  b.mesh.triangles.push_back({0, 1, 1});                    // repeated index
  b.triangle(Vec3(5, 0, 0), Vec3(6, 1, 1), Vec3(7, 2, 2));  // collinear
  EXPECT_EQ(analyze_topology(b.mesh).degenerate_triangles, 2);
}

// A fresh directory per test, removed afterwards.
class TempDir : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("poreshell-test-mesh-" + std::to_string(::getpid()) + "-" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::vector<fs::path> listing() const {
    std::vector<fs::path> names;
    for (const auto& e : fs::directory_iterator(dir_)) names.push_back(e.path().filename());
    std::sort(names.begin(), names.end());
    return names;
  }
  fs::path dir_;
};

using StlTest = TempDir;
using AtomicFileTest = TempDir;

TEST_F(StlTest, RoundTripKeepsTopologyAndVolume) {
  MeshBuilder b;
  b.box(Vec3(0.1, 0.2, 0.3), Vec3(1.7, 2.9, 3.3));
  b.box(Vec3(5, 5, 5), Vec3(6, 6.5, 7));
  const MeshTopology before = analyze_topology(b.mesh);
  const fs::path file = dir_ / "boxes.stl";
  write_stl_binary(file, b.mesh);
  EXPECT_EQ(fs::file_size(file), 84u + 50u * b.mesh.triangles.size());
  {
    std::ifstream in(file, std::ios::binary);
    std::string head(9, '\0');
    in.read(head.data(), 9);
    EXPECT_EQ(head, "poreshell");
  }
  const TriangleMesh back = read_stl_binary(file);
  const MeshTopology after = analyze_topology(back);
  EXPECT_EQ(back.triangles.size(), b.mesh.triangles.size());
  EXPECT_EQ(back.vertices.size(), b.mesh.vertices.size());
  expect_closed_manifold(after);
  EXPECT_EQ(after.euler_characteristic, before.euler_characteristic);
  EXPECT_NEAR(after.signed_volume, before.signed_volume, 1e-5 * before.signed_volume);
  EXPECT_EQ(listing(), std::vector<fs::path>{"boxes.stl"});
}

TEST_F(StlTest, MissingOrTruncatedFileIsAnInputError) {
  EXPECT_THROW(read_stl_binary(dir_ / "missing.stl"), InputError);
  MeshBuilder b;
  b.tetrahedron(Vec3(0, 0, 0), 1.0);
  const fs::path file = dir_ / "cut.stl";
  write_stl_binary(file, b.mesh);
  fs::resize_file(file, fs::file_size(file) - 10);
  EXPECT_THROW(read_stl_binary(file), InputError);
  fs::resize_file(file, 40);
  EXPECT_THROW(read_stl_binary(file), InputError);
}

TEST_F(AtomicFileTest, ReplacesFileAndLeavesNoTemporary) {
  const fs::path file = dir_ / "out.txt";
  write_atomically(
      file, [](std::ostream& out) { out << "first"; }, false);
  write_atomically(
      file, [](std::ostream& out) { out << "second"; }, false);
  std::ifstream in(file);
  std::string text;
  in >> text;
  EXPECT_EQ(text, "second");
  EXPECT_EQ(listing(), std::vector<fs::path>{"out.txt"});
}

TEST_F(AtomicFileTest, FailingWriterLeavesOldFileAndNoTemporary) {
  const fs::path file = dir_ / "out.txt";
  write_atomically(
      file, [](std::ostream& out) { out << "old"; }, false);
  EXPECT_THROW(write_atomically(file,
                                [](std::ostream& out) {
                                  out << "partial";
                                  throw std::runtime_error("writer failed");
                                }),
               std::runtime_error);
  std::ifstream in(file);
  std::string text;
  in >> text;
  EXPECT_EQ(text, "old");
  EXPECT_EQ(listing(), std::vector<fs::path>{"out.txt"});
}

TEST_F(AtomicFileTest, RefusesMissingOrUnwritableDirectory) {
  bool called = false;
  auto writer = [&](std::ostream& out) {
    called = true;
    out << "x";
  };
  try {
    write_atomically(dir_ / "no-such-dir" / "out.stl", writer);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("no-such-dir"), std::string::npos) << e.what();
  }
  // A regular file where the directory should be cannot be written even by root.
  { std::ofstream(dir_ / "plain") << "x"; }
  EXPECT_THROW(write_atomically(dir_ / "plain" / "out.stl", writer), InputError);
  EXPECT_FALSE(called);
  EXPECT_EQ(listing(), std::vector<fs::path>{"plain"});
}

}  // namespace
}  // namespace poreshell
