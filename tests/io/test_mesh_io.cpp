// Reading triangle meshes (io/mesh_io.hpp): every format gives the same tetrahedron, 3MF build items
// transformed; bad files give one clear error each; degenerate triangles are dropped and repeated
// vertices welded.

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "geometry/mesh.hpp"
#include "io/mesh_io.hpp"
#include "package_3mf.hpp"

using namespace poreshell;
namespace fs = std::filesystem;

namespace {

// ---------- files ----------

const std::vector<Vec3> kTetVertices{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
const std::vector<std::array<int, 3>> kTetTriangles{{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};

fs::path temp_dir() {
  const fs::path dir =
      fs::temp_directory_path() / ("poreshell_test_mesh_surface_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  return dir;
}

fs::path write_text(const std::string& name, const std::string& text) {
  const fs::path p = temp_dir() / name;
  std::ofstream(p, std::ios::binary) << text;
  return p;
}

std::string tet_ascii_stl() {
  std::string s = "solid tet\n";
  for (const auto& t : kTetTriangles) {
    s += "facet normal 0 0 0\nouter loop\n";
    for (int v : t) {
      const Vec3& p = kTetVertices[v];
      s += "vertex " + std::to_string(p.x()) + " " + std::to_string(p.y()) + " " + std::to_string(p.z()) +
           "\n";
    }
    s += "endloop\nendfacet\n";
  }
  return s + "endsolid tet\n";
}

std::string tet_binary_stl(std::uint32_t claimed_count, std::size_t written) {
  std::string s(80, ' ');
  s.replace(0, 6, "binary");  // a binary STL header must not start with "solid"
  s.append(reinterpret_cast<const char*>(&claimed_count), 4);
  for (std::size_t f = 0; f < written; ++f) {
    float data[12] = {};
    for (int c = 0; c < 3; ++c)
      for (int a = 0; a < 3; ++a)
        data[3 + 3 * c + a] = static_cast<float>(kTetVertices[kTetTriangles[f][c]][a]);
    s.append(reinterpret_cast<const char*>(data), sizeof data);
    s.append(2, '\0');
  }
  return s;
}

std::string tet_obj() {
  std::string s = "# tetrahedron\n";
  for (const Vec3& p : kTetVertices)
    s += "v " + std::to_string(p.x()) + " " + std::to_string(p.y()) + " " + std::to_string(p.z()) + "\n";
  for (const auto& t : kTetTriangles)
    s += "f " + std::to_string(t[0] + 1) + " " + std::to_string(t[1] + 1) + " " + std::to_string(t[2] + 1) +
         "\n";
  return s;
}

std::string tet_ply() {
  std::string s =
      "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
      "element face 4\nproperty list uchar int vertex_indices\nend_header\n";
  for (const Vec3& p : kTetVertices)
    s += std::to_string(p.x()) + " " + std::to_string(p.y()) + " " + std::to_string(p.z()) + "\n";
  for (const auto& t : kTetTriangles)
    s += "3 " + std::to_string(t[0]) + " " + std::to_string(t[1]) + " " + std::to_string(t[2]) + "\n";
  return s;
}

std::string tet_off() {
  std::string s = "OFF\n4 4 0\n";
  for (const Vec3& p : kTetVertices)
    s += std::to_string(p.x()) + " " + std::to_string(p.y()) + " " + std::to_string(p.z()) + "\n";
  for (const auto& t : kTetTriangles)
    s += "3 " + std::to_string(t[0]) + " " + std::to_string(t[1]) + " " + std::to_string(t[2]) + "\n";
  return s;
}

// Build item transform in 3MF order (row-vector convention): 90 degrees about z, then (10, 20, 30).
const char* kTransform3mf = "0 1 0 -1 0 0 0 0 1 10 20 30";
Vec3 apply_transform_3mf(const Vec3& p) {
  return Vec3(-p.y(), p.x(), p.z()) + Vec3(10, 20, 30);
}

std::string tet_3mf() {
  std::string model =
      "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<model unit=\"millimeter\" xml:lang=\"en-US\" "
      "xmlns=\"http://schemas.microsoft.com/3dmanufacturing/core/2015/02\">\n<resources>\n<object id=\"1\" "
      "type=\"model\">\n<mesh>\n<vertices>\n";
  for (const Vec3& p : kTetVertices)
    model += "<vertex x=\"" + std::to_string(p.x()) + "\" y=\"" + std::to_string(p.y()) + "\" z=\"" +
             std::to_string(p.z()) + "\"/>\n";
  model += "</vertices>\n<triangles>\n";
  for (const auto& t : kTetTriangles)
    model += "<triangle v1=\"" + std::to_string(t[0]) + "\" v2=\"" + std::to_string(t[1]) + "\" v3=\"" +
             std::to_string(t[2]) + "\"/>\n";
  model += "</triangles>\n</mesh>\n</object>\n</resources>\n<build>\n<item objectid=\"1\" transform=\"" +
           std::string(kTransform3mf) + "\"/>\n</build>\n</model>\n";
  return test_support::package_3mf(model);
}

// Each read triangle must be an original triangle (under `map`), same orientation.
void expect_tetrahedron(const TriangleMesh& m, Vec3 (*map)(const Vec3&)) {
  ASSERT_EQ(m.triangles.size(), 4u);
  ASSERT_EQ(m.vertices.size(), 4u);
  std::set<std::array<int, 3>> found;
  for (const auto& t : m.triangles) {
    std::array<int, 3> ids{};
    for (int c = 0; c < 3; ++c) {
      ids[c] = -1;
      for (int v = 0; v < 4; ++v)
        if ((m.vertices[t[c]] - map(kTetVertices[v])).norm() < 1e-6) ids[c] = v;
      ASSERT_GE(ids[c], 0) << "vertex " << m.vertices[t[c]].transpose() << " is not a tetrahedron corner";
    }
    // Rotate so the smallest index comes first; orientation is kept.
    while (ids[0] != std::min({ids[0], ids[1], ids[2]})) ids = {ids[1], ids[2], ids[0]};
    found.insert(ids);
  }
  std::set<std::array<int, 3>> expected;
  for (auto t : kTetTriangles) {
    while (t[0] != std::min({t[0], t[1], t[2]})) t = {t[1], t[2], t[0]};
    expected.insert(t);
  }
  EXPECT_EQ(found, expected);
}

Vec3 identity(const Vec3& p) {
  return p;
}

std::string input_error_message(const fs::path& p) {
  try {
    read_triangle_mesh(p);
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "no InputError for " << p;
  return {};
}

}  // namespace

// ---------- reading files ----------

TEST(MeshIO, ReadsEveryFormat) {
  expect_tetrahedron(read_triangle_mesh(write_text("tet.stl", tet_ascii_stl())), identity);
  expect_tetrahedron(read_triangle_mesh(write_text("tet_binary.STL", tet_binary_stl(4, 4))), identity);
  expect_tetrahedron(read_triangle_mesh(write_text("tet.obj", tet_obj())), identity);
  expect_tetrahedron(read_triangle_mesh(write_text("tet.ply", tet_ply())), identity);
  expect_tetrahedron(read_triangle_mesh(write_text("tet.off", tet_off())), identity);
  expect_tetrahedron(read_triangle_mesh(write_text("tet.3mf", tet_3mf())), apply_transform_3mf);
  MeshInputStats stats;
  read_triangle_mesh(temp_dir() / "tet.obj", &stats);
  EXPECT_EQ(stats.vertices, 4);
  EXPECT_EQ(stats.triangles, 4);
  EXPECT_EQ(stats.dropped_degenerate, 0);
  EXPECT_EQ(stats.boundary_edges, 0);
}

TEST(MeshIO, BadInputsGiveDistinctClearErrors) {
  const std::vector<std::pair<fs::path, std::string>> cases{
      {write_text("empty.stl", ""), "empty"},
      {write_text("truncated.stl", tet_binary_stl(4, 2)), "is truncated"},
      {write_text("nan.obj", "v 0 0 0\nv 1 0 0\nv 0 1 nan\nf 1 2 3\n"), "non-finite"},
      {temp_dir() / "missing.obj", "does not exist"},
      {write_text("points.xyz", "0 0 0\n"), "unsupported extension"},
      {write_text("mesh.foo", "0 0 0\n"), ".stl, .obj, .ply, .off, .3mf"},
      {write_text("broken.3mf", "not a zip archive"), "cannot read"},
      {write_text("lines.obj", "v 0 0 0\nv 1 0 0\nl 1 2\n"), "no triangles"},
  };
  std::set<std::string> messages;
  for (const auto& [path, expected] : cases) {
    const std::string message = input_error_message(path);
    EXPECT_NE(message.find(expected), std::string::npos) << message;
    EXPECT_NE(message.find(path.filename().string()), std::string::npos) << message;
    messages.insert(message);
    std::cout << "  " << message << "\n";
  }
  EXPECT_EQ(messages.size(), cases.size());
}

TEST(MeshIO, DegenerateTrianglesDroppedAndDuplicatesWelded) {
  // Tetrahedron whose vertex 1 appears twice (5 is a copy), plus a repeated-index and a zero-area
  // triangle that uses an extra vertex 6 on the line through 0 and 1.
  const std::string obj =
      "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nv 1 0 0\nv 2 0 0\n"
      "f 1 3 2\nf 1 5 4\nf 1 4 3\nf 2 3 4\nf 1 2 2\nf 1 2 6\n";
  MeshInputStats stats;
  const TriangleMesh m = read_triangle_mesh(write_text("degenerate.obj", obj), &stats);
  EXPECT_EQ(stats.dropped_degenerate, 2);
  EXPECT_EQ(stats.triangles, 4);
  EXPECT_EQ(stats.vertices, 4);
  EXPECT_EQ(stats.boundary_edges, 0);  // closed only because the copy was welded
  expect_tetrahedron(m, identity);

  TriangleMesh direct{{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 0, 0}, {0.5, 0, 0}},
                      {{0, 1, 2}, {0, 3, 2}, {0, 1, 4}, {2, 2, 1}}};
  const MeshInputStats s = clean_triangle_mesh(direct);
  EXPECT_EQ(s.dropped_degenerate, 2);
  EXPECT_EQ(s.vertices, 3);
  // The welded copy repeats the first triangle: since issue 47 a repeat is dropped and counted (thousands
  // of them made every later search slow), which leaves the one triangle, open.
  EXPECT_EQ(s.dropped_duplicate, 1);
  EXPECT_EQ(s.triangles, 1);
  EXPECT_EQ(s.boundary_edges, 3);
}
