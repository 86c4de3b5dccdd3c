// Printable outputs: every format round-trips through the reader (same triangles, closed, manifold,
// same volume up to float32 round-off), 3MF states millimetres, unknown extensions and failed writes
// leave nothing behind; the length units of --units.

#include <Model/COM/NMR_DLLInterfaces.h>
#include <gtest/gtest.h>
#include <tbb/global_control.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <string>

#include "core/error.hpp"
#include "core/units.hpp"
#include "geometry/isosurface.hpp"
#include "io/mesh_io.hpp"
#include "io/mesh_writers.hpp"

namespace poreshell {
namespace {

namespace fs = std::filesystem;

fs::path scratch_dir(const std::string& name) {
  const fs::path dir =
      fs::temp_directory_path() / ("poreshell-test-writers-" + std::to_string(::getpid()) + "-" + name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

// A closed, manifold solid with a tunnel: a torus shell of major radius 20 mm, tube radius 6 mm, and
// wall 2 mm, centred off the origin so that the written coordinates are not symmetric.
TriangleMesh torus_shell_mm() {
  const Grid grid(Vec3(-30.0, -30.0, -12.0) + Vec3(100.0, 50.0, 7.0), 0.7, {87, 87, 35});
  std::vector<Coord> points;
  std::vector<double> values;
  const Vec3 center(100.0, 50.0, 7.0);
  for (int k = 0; k < grid.dims()[2]; ++k)
    for (int j = 0; j < grid.dims()[1]; ++j)
      for (int i = 0; i < grid.dims()[0]; ++i) {
        const Vec3 p = grid.position({i, j, k}) - center;
        const double ring = std::hypot(std::hypot(p.x(), p.y()) - 20.0, p.z()) - 6.0;
        const double wall = std::abs(ring) - 1.0;
        if (wall > 2.0) continue;
        points.push_back({i, j, k});
        values.push_back(wall);
      }
  return extract_isosurface({&grid, points, values, 2.0}, 0.0);
}

std::string read_bytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

unsigned unit_of_3mf(const fs::path& path) {
  NMR::PLib3MFModel* model = nullptr;
  EXPECT_EQ(NMR::lib3mf_createmodel(&model), LIB3MF_OK);
  NMR::PLib3MFModelReader* reader = nullptr;
  EXPECT_EQ(NMR::lib3mf_model_queryreader(model, "3mf", &reader), LIB3MF_OK);
  EXPECT_EQ(NMR::lib3mf_reader_readfromfileutf8(reader, path.string().c_str()), LIB3MF_OK);
  DWORD unit = 99;
  EXPECT_EQ(NMR::lib3mf_model_getunit(model, &unit), LIB3MF_OK);
  NMR::lib3mf_release(reader);
  NMR::lib3mf_release(model);
  return unit;
}

TEST(MeshWriters, EveryFormatRoundTrips) {
  const TriangleMesh mesh = torus_shell_mm();
  const MeshTopology original = analyze_topology(mesh);
  ASSERT_TRUE(original.closed() && original.manifold() && original.oriented());
  ASSERT_EQ(original.euler_characteristic, 0);  // two nested tori
  const fs::path dir = scratch_dir("roundtrip");
  for (const char* ext : {".stl", ".3mf", ".obj", ".ply", ".STL"}) {
    const fs::path path = dir / (std::string("shell") + ext);
    write_mesh(path, mesh);
    const TriangleMesh back = read_triangle_mesh(path);
    const MeshTopology t = analyze_topology(back);
    EXPECT_EQ(t.triangles, original.triangles) << ext;
    EXPECT_EQ(t.vertices, original.vertices) << ext;
    EXPECT_TRUE(t.closed() && t.manifold() && t.oriented()) << ext;
    EXPECT_EQ(t.euler_characteristic, original.euler_characteristic) << ext;
    EXPECT_EQ(t.degenerate_triangles, 0) << ext;
    // float32 coordinates near 100 mm: relative round-off about 1e-7 per coordinate.
    EXPECT_NEAR(t.signed_volume / original.signed_volume, 1.0, 1e-5) << ext;
  }
  EXPECT_EQ(unit_of_3mf(dir / "shell.3mf"), static_cast<unsigned>(NMR::MODELUNIT_MILLIMETER));
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(dir)) names.push_back(e.path().filename().string());
  EXPECT_EQ(names.size(), 5u) << "no temporary files left behind";
}

TEST(MeshWriters, OutputIsTheSameBytesEveryTime) {
  const TriangleMesh mesh = torus_shell_mm();
  const fs::path dir = scratch_dir("bytes");
  for (const char* ext : {".stl", ".3mf", ".obj", ".ply"}) {
    write_mesh(dir / (std::string("a") + ext), mesh);
    write_mesh(dir / (std::string("b") + ext), mesh);
    EXPECT_TRUE(read_bytes(dir / (std::string("a") + ext)) == read_bytes(dir / (std::string("b") + ext)))
        << ext;
  }
}

// A 3MF large enough to be made of several chunks of vertices and of triangles (32,768 lines each),
// with coordinates from 0.001 to 500 mm: the reader gets back every float and every index exactly,
// whether one thread wrote it or all of them.
TEST(MeshWriters, Large3mfReadsBackExactly) {
  constexpr int kAround = 400, kTube = 200;  // 80,000 vertices, 160,000 triangles
  TriangleMesh mesh;
  for (int i = 0; i < kAround; ++i)
    for (int j = 0; j < kTube; ++j) {
      const double u = 2.0 * std::numbers::pi * i / kAround, v = 2.0 * std::numbers::pi * j / kTube;
      const double ring = 250.0 + 0.999 * 3.0 * std::cos(v);
      mesh.vertices.emplace_back(ring * std::cos(u) + 250.001, ring * std::sin(u) + 1.0 / 3.0,
                                 3.0 * std::sin(v) + 1e-3);
    }
  const auto at = [](int i, int j) { return (i % kAround) * kTube + j % kTube; };
  for (int i = 0; i < kAround; ++i)
    for (int j = 0; j < kTube; ++j) {
      mesh.triangles.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
      mesh.triangles.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
    }
  const fs::path dir = scratch_dir("large3mf");
  write_mesh(dir / "a.3mf", mesh);
  // What the reader makes of the exact floats (it numbers vertices in the order triangles use them).
  TriangleMesh expected = mesh;
  for (Vec3& p : expected.vertices) p = p.cast<float>().cast<double>();
  clean_triangle_mesh(expected);
  const TriangleMesh back = read_triangle_mesh(dir / "a.3mf");
  ASSERT_EQ(back.vertices.size(), expected.vertices.size());
  ASSERT_EQ(back.triangles.size(), expected.triangles.size());
  std::size_t moved = 0, renumbered = 0;
  for (std::size_t v = 0; v < back.vertices.size(); ++v) moved += back.vertices[v] != expected.vertices[v];
  for (std::size_t t = 0; t < back.triangles.size(); ++t)
    renumbered += back.triangles[t] != expected.triangles[t];
  EXPECT_EQ(moved, 0u);
  EXPECT_EQ(renumbered, 0u);

  {
    tbb::global_control one_thread(tbb::global_control::max_allowed_parallelism, 1);
    write_mesh(dir / "b.3mf", mesh);
  }
  EXPECT_TRUE(read_bytes(dir / "a.3mf") == read_bytes(dir / "b.3mf"));
}

TEST(MeshWriters, UnknownExtensionIsRefusedBeforeWriting) {
  const fs::path dir = scratch_dir("unknown");
  for (const char* name : {"shell.off", "shell", "shell.stl.gz", "shell.vtk"}) {
    try {
      check_output_extension(dir / name);
      ADD_FAILURE() << name << " was accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(".stl, .3mf, .obj, .ply"), std::string::npos) << e.what();
    }
    EXPECT_THROW(write_mesh(dir / name, torus_shell_mm()), InputError) << name;
  }
  EXPECT_TRUE(fs::is_empty(dir));
  EXPECT_NO_THROW(check_output_extension("x/y/shell.3MF"));
}

TEST(MeshWriters, FailedWriteLeavesNoFile) {
  const fs::path dir = scratch_dir("fail");
  const TriangleMesh mesh = torus_shell_mm();
  for (const char* ext : {".stl", ".3mf", ".obj", ".ply"})
    EXPECT_THROW(write_mesh(dir / "no-such-dir" / (std::string("x") + ext), mesh), InputError) << ext;
  EXPECT_THROW(write_mesh(dir / "empty.ply", TriangleMesh{}), InputError);
  EXPECT_TRUE(fs::is_empty(dir));
}

TEST(Units, MillimetresPerUnit) {
  EXPECT_EQ(millimetres_per(Unit::mm), 1.0);
  EXPECT_EQ(millimetres_per(Unit::cm), 10.0);
  EXPECT_EQ(millimetres_per(Unit::m), 1000.0);
  EXPECT_EQ(millimetres_per(Unit::inch), 25.4);
  EXPECT_STREQ(to_string(Unit::inch), "inch");
}

}  // namespace
}  // namespace poreshell
