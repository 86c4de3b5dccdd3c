#include <gtest/gtest.h>

#include <Eigen/Geometry>  // cross()
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <sstream>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "core/error.hpp"
#include "geometry/mesh.hpp"
#include "geometry/mesh_surface.hpp"
#include "input/vertex_field.hpp"
#include "test_support.hpp"

using namespace poreshell;
namespace fs = std::filesystem;

namespace {

// ---------- a small PLY writer, independent of the reader ----------

struct Property {
  Property(std::string item_type, std::string property_name, std::string list_count_type = "")
      : type(std::move(item_type)), name(std::move(property_name)), count_type(std::move(list_count_type)) {}
  std::string type, name;
  std::string count_type;  // non-empty: a list of `type` with a count of this type
};

struct Element {
  std::string name;
  std::vector<Property> properties;
  std::vector<std::vector<std::vector<double>>> rows;  // row -> property -> values (one unless a list)
};

template <class T>
void put(std::string& out, double value, bool big_endian) {
  const auto v = static_cast<T>(value);
  char bytes[sizeof v];
  std::memcpy(bytes, &v, sizeof v);
  if (big_endian) std::reverse(bytes, bytes + sizeof v);  // the tests run on little-endian hosts
  out.append(bytes, sizeof v);
}

void put_binary(std::string& out, const std::string& type, double value, bool big_endian) {
  if (type == "char" || type == "int8") return put<std::int8_t>(out, value, big_endian);
  if (type == "uchar" || type == "uint8") return put<std::uint8_t>(out, value, big_endian);
  if (type == "short" || type == "int16") return put<std::int16_t>(out, value, big_endian);
  if (type == "ushort" || type == "uint16") return put<std::uint16_t>(out, value, big_endian);
  if (type == "int" || type == "int32") return put<std::int32_t>(out, value, big_endian);
  if (type == "uint" || type == "uint32") return put<std::uint32_t>(out, value, big_endian);
  if (type == "float" || type == "float32") return put<float>(out, value, big_endian);
  if (type == "double" || type == "float64") return put<double>(out, value, big_endian);
  ADD_FAILURE() << "test writer: unknown type " << type;
}

std::string ply_file(const std::string& format, const std::vector<Element>& elements) {
  std::ostringstream header;
  header << "ply\nformat " << format << " 1.0\ncomment written by test_vertex_field\n";
  for (const Element& e : elements) {
    header << "element " << e.name << " " << e.rows.size() << "\n";
    for (const Property& p : e.properties)
      header << "property " << (p.count_type.empty() ? "" : "list " + p.count_type + " ") << p.type << " "
             << p.name << "\n";
  }
  header << "end_header\n";
  std::string data;
  const bool ascii = format == "ascii", big = format == "binary_big_endian";
  for (const Element& e : elements)
    for (const auto& row : e.rows) {
      std::ostringstream line;
      line.precision(17);
      for (std::size_t k = 0; k < row.size(); ++k) {
        const Property& p = e.properties[k];
        if (!p.count_type.empty()) {
          if (ascii)
            line << row[k].size() << " ";
          else
            put_binary(data, p.count_type, static_cast<double>(row[k].size()), big);
        }
        for (double v : row[k])
          if (ascii)
            line << v << " ";
          else
            put_binary(data, p.type, v, big);
      }
      if (ascii) data += line.str() + "\n";
    }
  return header.str() + data;
}

// The painted plane: a 4 x 4 grid of vertices (x, y) in {0..3}^2 on the tilted plane z = x/4 - y/2 + 1,
// as 9 quads (fans of 2 triangles), with the linear field f = x + 2y (0 to 9, exact in every type).
// Elements the reader must skip sit before, between and after the vertices and faces.
double plane_z(double x, double y) {
  return 0.25 * x - 0.5 * y + 1.0;
}
double plane_f(const Vec3& p) {
  return p.x() + 2.0 * p.y();
}
const Vec3 kPlaneNormal = Vec3(-0.25, 0.5, 1.0).normalized();

std::string painted_plane(const std::string& format, const std::string& value_type,
                          const std::string& count_type = "uchar", const std::string& index_type = "int") {
  Element camera{"camera", {{"float", "view_px"}, {"float", "view_py"}}, {{{1.5}, {2.5}}}};
  Element vertex{"vertex",
                 {{"float", "x"},
                  {"float", "y"},
                  {"float", "z"},
                  {"float", "nx"},
                  {value_type, "hole_scale"},
                  {"float", "uv", "uchar"},
                  {"uchar", "red"}},
                 {}};
  for (int j = 0; j < 4; ++j)
    for (int i = 0; i < 4; ++i)
      vertex.rows.push_back(
          {{double(i)}, {double(j)}, {plane_z(i, j)}, {0.5}, {i + 2.0 * j}, {0.1, 0.2}, {200}});
  Element edge{"edge", {{"int", "vertex1"}, {"int", "vertex2"}}, {{{0}, {1}}, {{1}, {2}}}};
  Element face{"face", {{"uchar", "flags"}, {index_type, "vertex_indices", count_type}}, {}};
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i) {
      const double a = 4 * j + i;
      face.rows.push_back({{7}, {a, a + 1, a + 5, a + 4}});
    }
  Element material{"material", {{"float", "ambient"}, {"uchar", "name", "uchar"}}, {{{0.2}, {65, 66}}}};
  return ply_file(format, {camera, vertex, edge, face, material});
}

// Checks the painted plane's field: vertex values, the linear field inside triangles, closest points
// off the surface and beyond its rim.
void expect_painted_plane(const VertexScalarField& field, const std::string& what) {
  ASSERT_EQ(field.vertex_count(), 16u) << what;
  EXPECT_EQ(field.triangle_count(), 18u) << what;
  EXPECT_TRUE(field.interpolates_on_faces()) << what;
  EXPECT_EQ(field.range(), std::make_pair(0.0, 9.0)) << what;
  for (int j = 0; j < 4; ++j)
    for (int i = 0; i < 4; ++i) EXPECT_EQ(field.at(Vec3(i, j, plane_z(i, j))), i + 2.0 * j) << what;
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(0.0, 3.0), off(-0.7, 0.7);
  for (int n = 0; n < 20; ++n) {
    const double x = u(rng), y = u(rng);
    const Vec3 q(x, y, plane_z(x, y));
    EXPECT_NEAR(field.at(q), plane_f(q), 1e-12) << what << " inside at " << q.transpose();
    EXPECT_NEAR(field.at(q + off(rng) * kPlaneNormal), plane_f(q), 1e-12) << what << " off the surface";
  }
}

}  // namespace

// ---------- reading ----------

TEST(VertexFieldPly, EveryFormatAndScalarTypeReadsThePaintedPlane) {
  TempDir dir;
  const std::vector<std::string> types{"char",  "uchar",  "short",   "ushort", "int",   "uint",
                                       "float", "double", "int8",    "uint8",  "int16", "uint16",
                                       "int32", "uint32", "float32", "float64"};
  for (const std::string format : {"ascii", "binary_little_endian", "binary_big_endian"})
    for (const std::string& type : types) {
      const fs::path p = dir.file(format + "-" + type + ".ply", painted_plane(format, type));
      expect_painted_plane(VertexScalarField::read_ply(p, "hole_scale"), format + " " + type);
    }
}

// The ends of each type's range: signedness and width of every type in every byte order.
TEST(VertexFieldPly, ExtremeValuesOfEachType) {
  TempDir dir;
  const double big = std::ldexp(1.0, 100);  // exact in float
  const std::vector<std::tuple<std::string, double, double>> types{{"char", -128, 127},
                                                                   {"uchar", 0, 255},
                                                                   {"short", -32768, 32767},
                                                                   {"ushort", 0, 65535},
                                                                   {"int", -2147483648.0, 2147483647.0},
                                                                   {"uint", 0, 4294967295.0},
                                                                   {"float", -big, 1.0 / big},
                                                                   {"double", -1e300, 1e300}};
  for (const std::string format : {"ascii", "binary_little_endian", "binary_big_endian"})
    for (const auto& [type, lo, hi] : types) {
      const Element vertex{"vertex",
                           {{"double", "x"}, {"double", "y"}, {"double", "z"}, {type, "v"}},
                           {{{0}, {0}, {0}, {lo}}, {{1}, {0}, {0}, {hi}}, {{0}, {1}, {0}, {0}}}};
      const Element face{"face", {{"int", "vertex_indices", "uchar"}}, {{{0, 1, 2}}}};
      const fs::path p = dir.file(format + "-" + type + ".ply", ply_file(format, {vertex, face}));
      const VertexScalarField field = VertexScalarField::read_ply(p, "v");
      EXPECT_EQ(field.range(), std::make_pair(lo, hi)) << format << " " << type;
      EXPECT_EQ(field.at(Vec3(-1, -1, 0)), lo) << format << " " << type;
      EXPECT_EQ(field.at(Vec3(2, 0, 1)), hi) << format << " " << type;
    }
}

TEST(VertexFieldPly, FaceListCountAndIndexTypesAndTheVertexIndexName) {
  TempDir dir;
  for (const std::string format : {"ascii", "binary_little_endian", "binary_big_endian"})
    for (const auto& [count, index] : std::vector<std::pair<std::string, std::string>>{{"uchar", "int"},
                                                                                       {"uint8", "uint32"},
                                                                                       {"int", "ushort"},
                                                                                       {"ushort", "uint"},
                                                                                       {"char", "short"}}) {
      std::string text = painted_plane(format, "float", count, index);
      if (count == "int") text.replace(text.find("vertex_indices"), 14, "vertex_index");  // also written so
      const fs::path p = dir.file(format + "-" + count + "-" + index + ".ply", text);
      expect_painted_plane(VertexScalarField::read_ply(p, "hole_scale"), format + " " + count + " " + index);
    }
}

TEST(VertexFieldPly, WindowsLineEndingsAndTheOtherPropertiesOfTheFile) {
  TempDir dir;
  std::string text;
  for (char ch : painted_plane("ascii", "float")) {
    if (ch == '\n') text += '\r';
    text += ch;
  }
  const fs::path p = dir.file("crlf.ply", text);
  expect_painted_plane(VertexScalarField::read_ply(p, "hole_scale"), "crlf");
  EXPECT_EQ(VertexScalarField::read_ply(p, "red").range(), std::make_pair(200.0, 200.0));
  EXPECT_NEAR(VertexScalarField::read_ply(p, "x").at(Vec3(2.5, 1, plane_z(2.5, 1))), 2.5, 1e-12);
  EXPECT_EQ(VertexScalarField::scalar_vertex_properties(p),
            (std::vector<std::string>{"x", "y", "z", "nx", "hole_scale", "red"}));
}

// ---------- interpolation ----------

// A tetrahedron, not planar: the value at a face's centroid is the mean of its corners, and so is the
// value at points outside along that face's normal.
TEST(VertexFieldInterpolation, BarycentricOnEachFaceOfAClosedMesh) {
  const std::vector<Vec3> v{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  const std::vector<double> f{0.0, 1.0, 2.0, 4.0};
  const std::vector<std::array<std::int32_t, 3>> tris{{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  const VertexScalarField field(v, f, tris, "test");
  EXPECT_EQ(field.name(), "test");
  for (const auto& t : tris) {
    const Vec3 c = (v[t[0]] + v[t[1]] + v[t[2]]) / 3.0;
    const Vec3 n = (v[t[1]] - v[t[0]]).cross(v[t[2]] - v[t[0]]).normalized();  // outward
    const double mean = (f[t[0]] + f[t[1]] + f[t[2]]) / 3.0;
    EXPECT_NEAR(field.at(c), mean, 1e-12);
    EXPECT_NEAR(field.at(c + 0.3 * n), mean, 1e-12);
    // On an edge: the mean of its two ends, from either triangle.
    EXPECT_NEAR(field.at(0.5 * (v[t[0]] + v[t[1]])), 0.5 * (f[t[0]] + f[t[1]]), 1e-12);
  }
  // Beyond a corner, the corner's value.
  EXPECT_NEAR(field.at(Vec3(3, -1, -1)), 1.0, 1e-12);
}

// Points anywhere around the plane, past its rim too: the value of the linear field at the closest point
// that MeshSurface gives.
TEST(VertexFieldInterpolation, PointsOffTheSurfaceTakeTheValueAtTheirClosestPoint) {
  TempDir dir;
  const VertexScalarField field = VertexScalarField::read_ply(
      dir.file("p.ply", painted_plane("binary_little_endian", "double")), "hole_scale");
  TriangleMesh mesh;
  for (int j = 0; j < 4; ++j)
    for (int i = 0; i < 4; ++i) mesh.vertices.emplace_back(i, j, plane_z(i, j));
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i) {
      const int a = 4 * j + i;
      mesh.triangles.push_back({a, a + 1, a + 5});
      mesh.triangles.push_back({a, a + 5, a + 4});
    }
  const MeshSurface surface(mesh);
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> u(-2.0, 5.0);
  for (int n = 0; n < 300; ++n) {
    const Vec3 p(u(rng), u(rng), u(rng));
    EXPECT_NEAR(field.at(p), plane_f(*surface.closest_point(p)), 1e-12) << p.transpose();
  }
}

// Zero-area triangles (collinear corners, a repeated vertex) interpolate along their nearest edge: no
// NaN. A sliver keeps its barycentric weights.
TEST(VertexFieldInterpolation, DegenerateTrianglesGiveFiniteEdgeValues) {
  const std::vector<Vec3> line{{0, 0, 0}, {1, 0, 0}, {2, 0, 0}};
  const VertexScalarField collinear(line, {0.0, 10.0, 20.0}, {{0, 1, 2}});
  EXPECT_NEAR(collinear.at(Vec3(0.5, 1, 0)), 5.0, 1e-12);
  EXPECT_NEAR(collinear.at(Vec3(1.5, 0, -3)), 15.0, 1e-12);
  EXPECT_NEAR(collinear.at(Vec3(-1, 0, 0)), 0.0, 1e-12);
  EXPECT_NEAR(collinear.at(Vec3(9, 1, 0)), 20.0, 1e-12);

  const std::vector<Vec3> sliver{{0, 0, 0}, {2, 0, 0}, {1, 1e-9, 0}};
  const VertexScalarField thin(sliver, {0.0, 2.0, 1.0}, {{0, 1, 2}});  // f = x on it
  std::mt19937 rng(2);
  std::uniform_real_distribution<double> u(-1.0, 3.0);
  for (int n = 0; n < 100; ++n) {
    const Vec3 p(u(rng), u(rng), u(rng));
    const double got = thin.at(p);
    ASSERT_TRUE(std::isfinite(got));
    EXPECT_NEAR(got, std::clamp(p.x(), 0.0, 2.0), 1e-6) << p.transpose();
  }

  // One good triangle next to one with a repeated vertex (skipped by MeshSurface): the good one answers.
  const VertexScalarField mixed({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {1.0, 2.0, 3.0}, {{0, 0, 1}, {0, 1, 2}});
  EXPECT_NEAR(mixed.at(Vec3(0.25, 0.25, 1.0)), 1.0 + 0.25 + 0.5, 1e-12);
}

// A field on part of a surface (two of a unit square's four triangles), asked on the surface: at()'s
// value on its faces, the outside value elsewhere, also on an edge it shares with the unpainted part only
// within reach; without faces, a vertex within reach answers.
TEST(VertexFieldInterpolation, AFieldOnPartOfASurfaceAnswersOnlyWithinReach) {
  const std::vector<Vec3> square{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {2, 0, 0}, {2, 1, 0}};
  const VertexScalarField painted(square, {1.0, 3.0, 5.0, 7.0, 0.0, 0.0}, {{0, 1, 2}, {0, 2, 3}});
  EXPECT_NEAR(painted.at_or(Vec3(0.25, 0.5, 0), 1e-6, -1.0), painted.at(Vec3(0.25, 0.5, 0)), 1e-12);
  EXPECT_NEAR(painted.at_or(Vec3(1.0, 0.5, 0), 1e-6, -1.0), 4.0, 1e-12);  // its edge x = 1
  EXPECT_EQ(painted.at_or(Vec3(1.5, 0.5, 0), 1e-6, -1.0), -1.0);
  EXPECT_EQ(painted.at_or(Vec3(0.5, 0.5, 0.1), 0.05, -1.0), -1.0);
  EXPECT_NEAR(painted.at_or(Vec3(0.5, 0.5, 0.1), 0.2, -1.0), painted.at(Vec3(0.5, 0.5, 0)), 1e-12);
  const VertexScalarField cloud({{0, 0, 0}, {1, 0, 0}}, {4.0, 5.0}, {});
  EXPECT_EQ(cloud.at_or(Vec3(0.9, 0, 0), 0.2, -1.0), 5.0);
  EXPECT_EQ(cloud.at_or(Vec3(0.5, 0, 0), 0.2, -1.0), -1.0);
}

// A painted point cloud (no faces, or only collapsed ones): the nearest vertex's value.
TEST(VertexFieldInterpolation, WithoutFacesTheNearestVertexAnswers) {
  TempDir dir;
  const fs::path p =
      dir.file("cloud.ply",
               "ply\nformat ascii 1.0\nelement vertex 3\nproperty double x\nproperty double y\n"
               "property double z\nproperty uchar keepout\nend_header\n0 0 0 0\n1 0 0 1\n"
               "3 0 0 0\n");
  const VertexScalarField cloud = VertexScalarField::read_ply(p, "keepout");
  EXPECT_FALSE(cloud.interpolates_on_faces());
  EXPECT_EQ(cloud.triangle_count(), 0u);
  EXPECT_EQ(cloud.at(Vec3(0.4, 5, 0)), 0.0);
  EXPECT_EQ(cloud.at(Vec3(0.6, -2, 0)), 1.0);
  EXPECT_EQ(cloud.at(Vec3(2.1, 0, 0)), 0.0);
  const VertexScalarField collapsed({{0, 0, 0}, {1, 0, 0}}, {4.0, 5.0}, {{0, 0, 1}});
  EXPECT_FALSE(collapsed.interpolates_on_faces());
  EXPECT_EQ(collapsed.at(Vec3(0.9, 0, 0)), 5.0);
}

// The pipeline's placement is a scale and an offset: after transform(), points of that frame give the
// values of the points they came from.
TEST(VertexFieldInterpolation, TransformMovesTheFieldWithItsVertices) {
  TempDir dir;
  const fs::path p = dir.file("p.ply", painted_plane("ascii", "float"));
  const VertexScalarField original = VertexScalarField::read_ply(p, "hole_scale");
  VertexScalarField placed = original;
  const auto to_frame = [](const Vec3& x) { return Vec3(0.1 * x + Vec3(0.5, -0.25, 2.0)); };
  placed.transform(to_frame);
  EXPECT_EQ(placed.range(), original.range());
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> u(-1.0, 4.0);
  for (int n = 0; n < 50; ++n) {
    const Vec3 x(u(rng), u(rng), u(rng));
    EXPECT_NEAR(placed.at(to_frame(x)), original.at(x), 1e-12);
  }
}

// ---------- bad input ----------

TEST(VertexFieldPly, BadInputsEachHaveTheirOwnMessage) {
  TempDir dir;
  const std::string head =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
      "property float quality\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";
  std::string truncated = painted_plane("binary_little_endian", "float");
  truncated.resize(truncated.size() - 40);  // into the faces (the material is 7 bytes)
  std::string truncated_vertices = painted_plane("binary_big_endian", "double");
  // 11 bytes of end_header, 8 of camera, 34 a vertex: the data ends in vertex 5.
  truncated_vertices.resize(truncated_vertices.find("end_header") + 200);
  std::string inf_binary = painted_plane("binary_little_endian", "float");
  const float inf = std::numeric_limits<float>::infinity();
  // Vertex 0's hole_scale: after the camera (8 bytes) and x, y, z, nx (16 bytes).
  std::memcpy(inf_binary.data() + inf_binary.find("end_header\n") + 11 + 8 + 16, &inf, sizeof inf);

  struct BadFile {
    std::string property;
    fs::path path;
    std::string expected;  // in the message
  };
  const std::vector<BadFile> cases{
      {"hole_scale", dir.file("never-written.ply", "") / "x.ply", "does not exist"},
      {"hole_scale", dir.file("mesh.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"), "is not a PLY file"},
      {"hole_scale", dir.file("empty.ply", ""), "is not a PLY file"},
      {"quality", dir.file("p.ply", painted_plane("ascii", "float")),
       "no scalar vertex property 'quality'; its scalar vertex properties are: x, y, z, nx, hole_scale, red"},
      {"quality",
       dir.file("on-faces.ply",
                "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
                "property float quality\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2 0.5\n"),
       "the file has it on its 'face' elements: transfer it to the vertices"},
      {"hole_scale", dir.file("truncated.ply", truncated),
       "is truncated: its header promises 9 'face' entries"},
      {"hole_scale", dir.file("truncated-vertices.ply", truncated_vertices),
       "is truncated or its header is wrong: the header promises 16 'vertex' entries"},
      {"quality", dir.file("truncated-ascii.ply", head + "0 0 0 1\n1 0 0 2\n0 1 0\n"), "is truncated"},
      {"quality", dir.file("nan.ply", head + "0 0 0 1\n1 0 0 nan\n0 1 0 3\n3 0 1 2\n"),
       "vertex 1 (counting from 0) has a NaN or infinite 'quality'"},
      {"hole_scale", dir.file("inf.ply", inf_binary),
       "vertex 0 (counting from 0) has a NaN or infinite 'hole_scale'"},
      {"quality", dir.file("nan-xyz.ply", head + "0 0 0 1\n1 inf 0 2\n0 1 0 3\n3 0 1 2\n"),
       "vertex 1 (counting from 0) has a NaN or infinite coordinate"},
      {"quality", dir.file("index.ply", head + "0 0 0 1\n1 0 0 2\n0 1 0 3\n3 0 1 7\n"),
       "face 0 (counting from 0) refers to vertex 7, but the file has 3 vertices (0 to 2)"},
      {"quality", dir.file("negative.ply", head + "0 0 0 1\n1 0 0 2\n0 1 0 3\n3 0 -1 2\n"),
       "refers to vertex -1"},
      {"quality", dir.file("word.ply", head + "0 0 0 1\n1 0 0 two\n0 1 0 3\n3 0 1 2\n"),
       "'vertex' entry 1 (counting from 0): 'two' is not a number"},
      {"quality", dir.file("count.ply", head + "0 0 0 1\n1 0 0 2\n0 1 0 3\n-3 0 1 2\n"),
       "the list length -3 is not a count"},
      {"quality",
       dir.file("type.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float128 x\nend_header\n"),
       "header line 4: unknown property type 'float128'"},
      {"quality", dir.file("format.ply", "ply\nformat binary 1.0\nend_header\n"), "unknown format 'binary'"},
      {"quality", dir.file("no-data.ply", head.substr(0, head.size() - 1)), "is truncated"},
      {"quality", dir.file("no-end.ply", "ply\nformat ascii 1.0\nelement vertex 1\n"),
       "no 'end_header' line"},
      {"quality", dir.file("no-vertices.ply", "ply\nformat ascii 1.0\nelement face 0\nend_header\n"),
       "has no vertices"},
      {"quality",
       dir.file("no-z.ply",
                "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n"
                "property float y\nproperty float quality\nend_header\n0 0 1\n"),
       "its vertices have no scalar 'z' coordinate"},
      {"quality",
       dir.file("no-list.ply",
                "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n"
                "property float y\nproperty float z\nproperty float quality\n"
                "element face 1\nproperty int a\nend_header\n0 0 0 1\n5\n"),
       "its faces have no 'vertex_indices' list"},
  };
  for (const BadFile& c : cases) {
    const std::string msg = input_error([&] { VertexScalarField::read_ply(c.path, c.property); });
    EXPECT_NE(msg.find(c.expected), std::string::npos) << c.path << ": '" << msg << "'";
  }
}
