// The bad-input table of docs/reliability.md, end to end: each row runs the program on a file the test
// writes and checks the exit code, exactly one "poreshell: error:" line that names the problem and the
// fix, and an output folder left empty.

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <vector>

#include "package_3mf.hpp"
#include "process.hpp"

#ifndef PORESHELL_EXE
#error "PORESHELL_EXE must name the poreshell executable (see tests/CMakeLists.txt)"
#endif

namespace {

namespace fs = std::filesystem;

// A run small enough to finish at once if a row's input were accepted.
const std::string kSmallRun = "--resolution 33 --alpha 84 --max-steps 5 --tol 1e-12 --quiet";

struct Row {
  std::string name;             // the table's row
  std::string file;             // written in the input folder (empty: none)
  std::string content;          // of `file`
  std::string args;             // the input options; FILE stands for the file's path
  int exit_code = 1;            // 2: a usage error
  std::string problem;          // the message names the problem...
  std::string fix;              // ...and what to do
  std::string run = kSmallRun;  // the rest of the command line
};

// Option rows: the default sphere, so that a row's options conflict with nothing here.
const std::string kOptionRun = "--max-steps 5 --tol 1e-12 --quiet";

using poreshell::test_support::lines;
using poreshell::test_support::package_3mf;
using poreshell::test_support::read_file;
using poreshell::test_support::run_program;
using poreshell::test_support::stored_zip;

// For the shell; appended piece by piece, since "'" + s + "'" trips g++ 12's -Wrestrict false positive.
std::string quoted(const fs::path& p) {
  std::string s = "'";
  s += p.string();
  s += '\'';
  return s;
}

std::string u32(std::uint32_t n) {
  std::string s(4, '\0');
  std::memcpy(s.data(), &n, 4);  // little-endian, as STL
  return s;
}

std::string f32s(std::initializer_list<float> values) {
  std::string s;
  for (float v : values) s.append(reinterpret_cast<const char*>(&v), 4);
  return s;
}

// A binary STL of one tetrahedron; `claimed` triangles in the header, `facets` written.
std::string binary_stl(std::uint32_t claimed, int facets) {
  const float v[4][3] = {{0, 0, 0}, {10, 0, 0}, {0, 10, 0}, {0, 0, 10}};
  const int t[4][3] = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  std::string s = std::string("binary") + std::string(74, ' ') + u32(claimed);
  for (int f = 0; f < facets; ++f) {
    s += f32s({0, 0, 0});
    for (int c = 0; c < 3; ++c) s += f32s({v[t[f][c]][0], v[t[f][c]][1], v[t[f][c]][2]});
    s += std::string(2, '\0');
  }
  return s;
}

std::string tet_obj(const std::string& scale) {
  return "v 0 0 0\nv " + scale + " 0 0\nv 0 " + scale + " 0\nv 0 0 " + scale +
         "\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";
}

const std::string kPlyHead =
    "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
    "element face 4\nproperty list uchar int vertex_indices\nend_header\n";
const std::string kPlyVertices = "0 0 0\n10 0 0\n0 10 0\n0 0 10\n";
const std::string kPlyFaces = "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";

std::string little_endian_tet_ply(const std::string& format) {
  std::string s = "ply\nformat " + format +
                  " 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
                  "element face 4\nproperty list uchar int vertex_indices\nend_header\n";
  s += f32s({0, 0, 0, 10, 0, 0, 0, 10, 0, 0, 0, 10});
  const std::int32_t t[4][3] = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  for (const auto& f : t) {
    s += '\3';
    s.append(reinterpret_cast<const char*>(f), sizeof f);
  }
  return s;
}

std::string package_3mf(const std::string& resources, const std::string& build) {
  const std::string model =
      "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<model unit=\"millimeter\" xml:lang=\"en-US\" "
      "xmlns=\"http://schemas.microsoft.com/3dmanufacturing/core/2015/02\"><resources>" +
      resources + "</resources><build>" + build + "</build></model>\n";
  return package_3mf(model);
}

// A closed 20 mm cube (8 corners, 12 triangles, outward), its corner 7 moved to `far` on each axis.
struct Cube {
  std::vector<std::array<double, 3>> v;
  std::vector<std::array<int, 3>> t = {{0, 2, 1}, {0, 3, 2}, {4, 5, 6}, {4, 6, 7}, {0, 1, 5}, {0, 5, 4},
                                       {2, 3, 7}, {2, 7, 6}, {1, 2, 6}, {1, 6, 5}, {0, 4, 7}, {0, 7, 3}};
  explicit Cube(double far) {
    for (int k = 0; k < 8; ++k)
      v.push_back({20.0 * (k == 1 || k == 2 || k == 5 || k == 6),
                   20.0 * (k == 2 || k == 3 || k == 6 || k == 7), 20.0 * (k >= 4)});
    v[7] = {far, far, far};
  }
};

std::string far_cube_obj(double far) {
  const Cube c(far);
  std::ostringstream s;
  s.precision(17);
  for (const auto& p : c.v) s << "v " << p[0] << ' ' << p[1] << ' ' << p[2] << '\n';
  for (const auto& t : c.t) s << "f " << t[0] + 1 << ' ' << t[1] + 1 << ' ' << t[2] + 1 << '\n';
  return s.str();
}

std::string far_cube_stl(float far) {
  const Cube c(far);
  std::string s = std::string(80, ' ') + u32(12);
  for (const auto& t : c.t) {
    s += f32s({0, 0, 0});
    for (int k : t) s += f32s({float(c.v[k][0]), float(c.v[k][1]), float(c.v[k][2])});
    s += std::string(2, '\0');
  }
  return s;
}

std::string far_cube_ply(double far) {
  const Cube c(far);
  std::string s =
      "ply\nformat binary_little_endian 1.0\nelement vertex 8\nproperty double x\nproperty double y\n"
      "property double z\nelement face 12\nproperty list uchar int vertex_indices\nend_header\n";
  for (const auto& p : c.v) s.append(reinterpret_cast<const char*>(p.data()), 24);
  for (const auto& t : c.t) {
    s += '\3';
    for (int k : t) s += u32(static_cast<std::uint32_t>(k));
  }
  return s;
}

std::string repeated(const std::string& line, std::size_t n) {
  std::string s;
  s.reserve(line.size() * n);
  for (std::size_t i = 0; i < n; ++i) s += line;
  return s;
}

// Every bad input, one row each (docs/reliability.md numbers them): as long as the cases are many, and
// kept whole so that the table reads as one list.
std::vector<Row> rows() {
  const std::string ascii_tet =
      "solid t\n"
      "facet normal 0 0 0\nouter loop\nvertex 0 0 0\nvertex 0 10 0\nvertex 10 0 0\nendloop\nendfacet\n"
      "facet normal 0 0 0\nouter loop\nvertex 0 0 0\nvertex 10 0 0\nvertex 0 0 inf\nendloop\nendfacet\n"
      "endsolid t\n";
  std::vector<Row> r = {
      {"missing file", "", "", "--mesh nowhere.stl", 1, "does not exist", "check the path"},
      {"a folder", "", "", "--mesh FOLDER", 1, "is a folder", "give the path of a file"},
      {"unknown extension in (mesh)", "m.vtk", "x", "--mesh FILE", 1, "unsupported extension '.vtk'",
       "use one of"},
      {"unknown extension in (points)", "p.las", "x", "--points FILE", 1, "unknown point file extension",
       "use .xyz"},
      {"unknown extension out", "m.obj", tet_obj("10"), "--mesh FILE -o out.vtk", 1, ".vtk", ".stl"},
      {"empty binary STL", "e.stl", "", "--mesh FILE", 1, "is empty (0 bytes)", "give a complete .stl"},
      {"empty OBJ", "e.obj", "", "--mesh FILE", 1, "is empty (0 bytes)", "give a complete .obj"},
      {"empty PLY mesh", "e.ply", "", "--mesh FILE", 1, "is empty (0 bytes)", "give a complete .ply"},
      {"empty OFF", "e.off", "", "--mesh FILE", 1, "is empty (0 bytes)", "give a complete .off"},
      {"empty 3MF", "e.3mf", "", "--mesh FILE", 1, "is empty (0 bytes)", "give a complete .3mf"},
      {"empty XYZ", "e.xyz", "", "--points FILE", 1, "is empty", "give a file"},
      {"empty PLY points", "e.ply", "", "--points FILE", 1, "is empty", "give a file"},
      {"truncated binary STL", "t.stl", binary_stl(4, 2), "--mesh FILE", 1, "is truncated", "re-export"},
      {"STL claiming 1e9 triangles", "c.stl", binary_stl(1000000000, 1), "--mesh FILE", 1,
       "declares 1000000000 triangles", "re-export"},
      {"garbage text STL", "g.stl", "hello, this is not a mesh\n", "--mesh FILE", 1, "is not an STL file",
       "re-export it as STL"},
      {"garbage ASCII STL body", "g.stl", "solid x\nhello world\n", "--mesh FILE", 1,
       "line 2: unexpected 'hello'", "re-export"},
      {"garbage text OBJ", "g.obj", "hello world\nthis is not a mesh\n", "--mesh FILE", 1,
       "contains no triangles", "give a surface mesh"},
      {"garbage text OFF", "g.off", "hello world\n", "--mesh FILE", 1, "expected the vertex count",
       "re-export"},
      {"garbage text PLY", "g.ply", "hello world\n", "--mesh FILE", 1, "is not a PLY file",
       "give a PLY file"},
      {"garbage text XYZ", "g.xyz", "hello world\n", "--points FILE", 1, "line 1: expected three numbers",
       "one point a line"},
      {"NaN coordinate (OBJ)", "n.obj", tet_obj("nan"), "--mesh FILE", 1, "non-finite coordinate",
       "re-export the mesh"},
      {"Inf coordinate (ASCII STL)", "i.stl", ascii_tet, "--mesh FILE", 1, "non-finite coordinate",
       "re-export the mesh"},
      {"NaN coordinate (XYZ)", "n.xyz", "0 0 0\n1 nan 0\n", "--points FILE", 1, "point 2 has a NaN",
       "remove or fix it"},
      {"Inf coordinate (PLY points)", "i.ply",
       "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\nproperty float z\n"
       "end_header\n0 0 inf\n1 0 0\n",
       "--points FILE", 1, "point 1 has a NaN or infinite", "remove or fix it"},
      {"index out of range (OBJ)", "o.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n", "--mesh FILE", 1,
       "refers to vertex 9", "re-export"},
      {"negative index (OBJ, counting back too far)", "o.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -1 -2 -9\n",
       "--mesh FILE", 1, "refers to vertex -9", "re-export"},
      {"index out of range (OFF)", "o.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n", "--mesh FILE", 1,
       "face 0 refers to vertex 7", "re-export"},
      {"negative index (OFF)", "o.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 -1 2\n", "--mesh FILE", 1,
       "refers to vertex -1", "re-export"},
      {"index out of range (PLY)", "o.ply", kPlyHead + kPlyVertices + "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 4\n",
       "--mesh FILE", 1, "face 3 (counting from 0) refers to vertex 4", "re-export"},
      {"negative index (PLY)", "o.ply", kPlyHead + kPlyVertices + "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 -2 3\n",
       "--mesh FILE", 1, "refers to vertex -2", "re-export"},
      {"only degenerate triangles", "d.obj", "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\nf 1 1 2\n", "--mesh FILE",
       1, "no usable triangles", "give a mesh whose faces enclose some area"},
      {"collinear points", "c.xyz",
       "0 0 0\n1 1 1\n2 2 2\n3 3 3\n4 4 4\n5 5 5\n6 6 6\n7 7 7\n8 8 8\n9 9 9\n10 10 10\n", "--points FILE", 1,
       "lies on a line", "give points spread over the surface"},
      {"one point", "one.xyz", "1 2 3\n", "--points FILE", 1, "has zero size",
       "give points that sample a surface"},
      {"1e6 identical points", "same.xyz", repeated("1 2 3\n", 1000000), "--points FILE", 1, "has zero size",
       "give points that sample a surface"},
      {"1e6 duplicate vertices, all triangles degenerate", "dup.obj",
       repeated("v 1 2 3\n", 1000000) + "f 1 2 3\nf 4 5 6\nf -1 -2 -3\n", "--mesh FILE", 1,
       "no usable triangles", "give a mesh whose faces enclose some area"},
      {"coordinates of 1e30", "big.obj", tet_obj("1e30"), "--mesh FILE", 1, "mm across", "check --units"},
      {"coordinates of 1e-30", "small.obj", tet_obj("1e-30"), "--mesh FILE", 1,
       "smaller than poreshell makes", "check --units"},
      {"PLY header lies: 1e9 vertices in a small file", "l.ply",
       "ply\nformat binary_little_endian 1.0\nelement vertex 1000000000\nproperty float x\nproperty float y\n"
       "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n" +
           std::string(60, '\0'),
       "--mesh FILE", 1, "promises 1000000000 'vertex' entries", "re-export"},
      {"PLY header lies: list longer than the data", "l.ply",
       kPlyHead + kPlyVertices + "3 0 2 1\n3 0 1 3\n3 0 3 2\n200 1 2 3\n", "--mesh FILE", 1, "is truncated",
       "re-export"},
      {"PLY header lies: big-endian, little-endian data", "be.ply",
       little_endian_tet_ply("binary_big_endian"), "--mesh FILE", 1, "refers to vertex", "re-export"},
      {"PLY header: unknown type", "u.ply",
       "ply\nformat ascii 1.0\nelement vertex 1\nproperty float128 x\nend_header\n0\n", "--mesh FILE", 1,
       "unknown property type 'float128'", "re-export"},
      {"PLY header: unknown format", "u.ply", "ply\nformat binary 1.0\nend_header\n", "--mesh FILE", 1,
       "unknown format 'binary'", "re-export"},
      {"PLY points: header lies", "l.ply",
       "ply\nformat ascii 1.0\nelement vertex 1000000\nproperty float x\nproperty float y\nproperty float z\n"
       "end_header\n0 0 0\n",
       "--points FILE", 1, "promises 1000000 'vertex' entries", "re-export"},
      {"garbage zip named .3mf", "g.3mf", stored_zip({{"junk.bin", "garbage garbage garbage"}}), "--mesh FILE", 1,
       "cannot read mesh file", "valid .3mf"},
      {"not a zip named .3mf", "g.3mf", "this is not a zip archive\n", "--mesh FILE", 1,
       "cannot read mesh file", "valid .3mf"},
      {"3MF with no object", "n.3mf", package_3mf("", ""), "--mesh FILE", 1, "contains no triangles",
       "give a surface mesh"},
      {"XYZ with text lines", "t.xyz", "0 0 0\n1 0 0\nvertex three\n0 1 0\n", "--points FILE", 1,
       "line 3: expected three numbers", "one point a line"},
      {"XYZ with two columns", "two.xyz", "0 0\n1 0\n0 1\n", "--points FILE", 1,
       "line 1: expected three numbers", "one point a line"},
      {"--mesh with --points", "m.obj", tet_obj("10"), "--mesh FILE --points FILE", 2, "excludes",
       "poreshell --help"},
      {"--resolution 0", "", "", "--resolution 0", 2, "--resolution: must be a number > 0, got '0'",
       "see poreshell --help", kOptionRun},
      {"--resolution 1", "", "", "--resolution 1", 1, "--resolution must be a whole number", "from 9 to 2048; got 1",
       kOptionRun},
      {"--resolution 3", "", "", "--resolution 3", 1, "--resolution must be a whole number", "from 9 to 2048; got 3",
       kOptionRun},
      {"--resolution 100000", "", "", "--resolution 100000", 1, "--resolution must be a whole number",
       "from 9 to 2048; got 100000", kOptionRun},
      {"--resolution malformed", "", "", "--resolution 12x", 2, "got '12x'", "see poreshell --help",
       kOptionRun},
      {"--hole-diameter negative", "", "", "--hole-diameter -5", 2, "--hole-diameter: must be a number > 0",
       "see poreshell --help", kOptionRun},
      {"--hole-diameter zero", "", "", "--hole-diameter 0", 2, "--hole-diameter: must be a number > 0",
       "see poreshell --help", kOptionRun},
      {"--hole-diameter NaN", "", "", "--hole-diameter nan", 2, "got 'nan'", "see poreshell --help",
       kOptionRun},
      {"--hole-diameter huge", "", "", "--hole-diameter 1e9", 1, "holes this large leave only",
       "ask for smaller holes", kOptionRun},
      {"--spacing below the diameter", "", "", "--hole-diameter 5 --spacing 4", 1,
       "would leave bridges too thin", "the nearest feasible requests are", kOptionRun},
      {"--spacing infinite", "", "", "--spacing inf", 2, "--spacing: must be a number > 0",
       "see poreshell --help", kOptionRun},
      {"--porosity above what holes give", "", "", "--hole-diameter 5 --porosity 0.95", 1,
       "--porosity 0.95 is outside", "use a porosity between", kOptionRun},
      {"--wall 0", "", "", "--wall 0", 2, "--wall: must be a number > 0", "see poreshell --help", kOptionRun},
      {"--wall 1e6", "", "", "--wall 1e6 --resolution 33", 1, "too large for this --wall",
       "ask for a wall well below", kOptionRun},
      {"--alpha negative", "", "", "--alpha -1", 2, "--alpha: must be a number >= 0", "see poreshell --help",
       kOptionRun},
      {"--tol 0", "", "", "--tol 0", 2, "--tol: must be a number > 0", "see poreshell --help", kOptionRun},
      {"--max-steps 0", "", "", "--max-steps 0", 2, "--max-steps: must be a number > 0",
       "see poreshell --help", kOptionRun},
      {"--threads -1", "", "", "--threads -1", 2, "--threads: must be a number >= 0", "see poreshell --help",
       kOptionRun},
      {"--threads 100000", "", "", "--threads 100000", 1, "--threads must be a whole number",
       "from 0 to 4096; got 100000 (worker threads; 0: all cores)", kOptionRun},
      {"--iso out of range", "", "", "--iso 2", 1, "--iso must be numbers", "strictly between -1 and 1; got 2",
       kOptionRun},
      {"--iso malformed", "", "", "--iso 0.3,abc", 2, "--iso", "see poreshell --help", kOptionRun},
      {"--phi-bar out of range", "", "", "--phi-bar 2", 1, "--phi-bar must be a number",
       "strictly between -1 and 1; got 2", kOptionRun},
      {"--epsilon-m negative", "", "", "--epsilon-m -1", 2, "--epsilon-m: must be a number > 0",
       "see poreshell --help", kOptionRun},
      {"--dt-h 0", "", "", "--dt-h 0", 2, "--dt-h: must be a number > 0", "see poreshell --help", kOptionRun},
      {"--voxel-size 0", "", "", "--voxel-size 0", 2, "--voxel-size: must be a number > 0",
       "see poreshell --help", kOptionRun},
      {"--voxel-size too fine", "", "", "--voxel-size 1e-6", 1,
       "grid points along the longest side (at most 2048)", "choose a larger voxel size", kOptionRun},
      {"--grade malformed axis", "", "", "--hole-diameter 6 --grade axis:q:4:8", 1, "--grade 'axis:q:4:8'",
       "the axis is x, y or z", kOptionRun},
      {"--grade with NaN", "", "", "--hole-diameter 6 --grade axis:z:nan:8", 1, "'nan' is not a number",
       "use axis:x|y|z:D1:D2", kOptionRun},
      {"--keep-out with NaN", "", "", "--keep-out 1,2,nan,4", 2, "--keep-out '1,2,nan,4' is not X,Y,Z,R",
       "four numbers, mm", kOptionRun},
      {"--keep-out with three numbers", "", "", "--keep-out 1,2,3", 2, "--keep-out '1,2,3' is not X,Y,Z,R",
       "four numbers, mm", kOptionRun},
      {"--keep-out negative radius", "", "", "--keep-out 1,2,3,-4", 1, "--keep-out takes X,Y,Z,R",
       "a radius R > 0", kOptionRun},
      {"--keep-out-box with five numbers", "", "", "--keep-out-box 0,0,0,1,1", 2, "is not X0,Y0,Z0,X1,Y1,Z1",
       "six numbers, mm", kOptionRun},
      {"--keep-out-box with Inf", "", "", "--keep-out-box 0,0,0,inf,1,1", 2, "is not X0,Y0,Z0,X1,Y1,Z1",
       "six numbers, mm", kOptionRun},
      {"--keep-out-box inverted", "", "", "--keep-out-box 1,0,0,0,1,1", 1,
       "--keep-out-box takes X0,Y0,Z0,X1,Y1,Z1", "with X0 < X1", kOptionRun},
      {"--rim negative", "", "", "--rim -1", 2, "--rim: must be a number >= 0", "see poreshell --help",
       kOptionRun},
      {"--max-triangles negative", "", "", "--max-triangles -5", 2, "--max-triangles: must be a number >= 0",
       "see poreshell --help", kOptionRun},
      {"--max-triangles out of reach", "", "", "--resolution 40 --max-triangles 50 --max-deviation 0.01", 1,
       "--max-triangles 50 cannot be met within --max-deviation 0.01 mm", "ask for at least", kOptionRun},
      {"--max-deviation negative", "", "", "--max-deviation -1", 2, "--max-deviation: must be a number >= 0",
       "see poreshell --help", kOptionRun},
      {"--max-memory 0", "", "", "--max-memory 0", 2, "--max-memory: must be a number > 0",
       "see poreshell --help", kOptionRun},
      {"--max-seconds 0", "", "", "--max-seconds 0", 2, "--max-seconds: must be a number > 0",
       "see poreshell --help", kOptionRun},
      {"--scale NaN", "", "", "--scale nan", 2, "--scale: must be a number > 0, got 'nan'",
       "see poreshell --help", kOptionRun},
      {"--seed negative", "", "", "--seed -1", 2, "--seed: must be a number >= 0", "see poreshell --help",
       kOptionRun},
      {"--units unknown", "", "", "--units furlong", 2, "'furlong' is not one of cm, inch, m, mm",
       "see poreshell --help", kOptionRun},
      {"--offset unknown", "", "", "--offset sideways", 2,
       "'sideways' is not one of centered, inside, outside", "see poreshell --help", kOptionRun},
      {"--stop unknown", "", "", "--stop sometimes", 2, "'sometimes' is not one of auto, holes, paper",
       "see poreshell --help", kOptionRun},
      {"--layout cvt without holes in mm", "", "", "--layout cvt", 1,
       "--layout cvt places holes at the spacing asked in mm", "add --hole-diameter MM", kOptionRun},
      {"--alpha with --hole-diameter", "", "", "--hole-diameter 5 --alpha 2200", 2,
       "--alpha excludes --hole-diameter", "see poreshell --help", kOptionRun},
      {"misspelt option", "", "", "--resolutoin 131", 2, "unknown argument '--resolutoin'",
       "did you mean --resolution?", kOptionRun},
      {"option given twice", "", "", "--wall 2 --wall 3", 2, "--wall given more than once", "give it once",
       kOptionRun},
      {"no output", "", "", "--resolution 33", 2, "no output file", "give -o OUT.stl", kOptionRun},
      {"unknown extension out", "", "", "--resolution 33 -o out.vtk", 1, ".vtk", ".stl", kOptionRun},
      {"output folder does not exist", "", "", "--resolution 33 -o /nonexistent-poreshell/out.stl", 1,
       "the directory '/nonexistent-poreshell' does not exist", "create it or choose another", kOptionRun},
      {"output folder cannot be written", "", "", "--resolution 33 -o /proc/out.stl", 1,
       "cannot create a file in '/proc'", "check that the directory is writable", kOptionRun},
      // Issue 47: geometry a reader would drop without a word is refused, naming the line or element.
      {"vertex at 1e16 mm (OBJ cube)", "far.obj", far_cube_obj(1e16), "--mesh FILE", 1,
       "vertex 7 (counting from 0, as imported) at (1e+16", "remove or fix the vertex"},
      {"vertex at 3.4e38 (binary STL cube)", "far.stl", far_cube_stl(3.4e38f), "--mesh FILE", 1,
       "lies far outside the rest of the mesh", "remove or fix the vertex"},
      {"vertex at 1e308 (binary PLY cube)", "far.ply", far_cube_ply(1e308), "--mesh FILE", 1,
       "vertex 7 (counting from 0, as imported) at (1e+308", "remove or fix the vertex"},
      {"ASCII PLY face line short of an index", "s.ply", kPlyHead + kPlyVertices + "3 0 2\n3 0 1 3\n3 0 3 2\n3 1 2 3\n",
       "--mesh FILE", 1, "'face' entry 0 (counting from 0): line 14 ends before the row does", "re-export"},
      {"ASCII PLY face line with a value too many", "x.ply",
       kPlyHead + kPlyVertices + "3 0 2 1\n3 0 1 3 2\n3 0 3 2\n3 1 2 3\n", "--mesh FILE", 1,
       "line 15 has values after the row's last property", "re-export"},
      {"ASCII PLY with data after its last element", "t.ply", kPlyHead + kPlyVertices + kPlyFaces + "3 0 1 2\n",
       "--mesh FILE", 1, "has data after its last element ('3' on line 18)", "re-export"},
      {"binary PLY face of 0 vertices", "z.ply", [] {
         std::string s = little_endian_tet_ply("binary_little_endian");
         s.replace(s.find("element face 4"), 14, "element face 5");
         return s + '\0';
       }(),
       "--mesh FILE", 1, "face 4 (counting from 0) has 0 vertices", "re-export"},
      {"OBJ line starting with a NUL byte", "nul.obj", tet_obj("10") + std::string("\0f 1 2 3\n", 9), "--mesh FILE",
       1, "line 9: a NUL byte", "re-export"},
      {"ASCII STL facet with 4 vertices", "q.stl",
       "solid q\nfacet normal 0 0 0\nouter loop\nvertex 0 0 0\nvertex 10 0 0\nvertex 10 10 0\nvertex 0 10 "
       "0\nendloop\nendfacet\nendsolid q\n",
       "--mesh FILE", 1, "line 8: a facet with 4 vertices", "re-export"},
      // Issue 47: a request that cannot be met says so before the run, naming what to change.
      {"holes larger than the model (metres read as mm)", "m.obj", tet_obj("0.15"), "--mesh FILE --hole-diameter 8",
       1, "fit nowhere on it", "say --units m", kOptionRun},
      {"holes wider than the model", "w.obj", tet_obj("70"), "--mesh FILE --hole-diameter 100", 1,
       "holes of 100 mm fit nowhere on it", "ask for --hole-diameter well under", kOptionRun},
      // Issue 47: every output path is checked before the run, not only -o's.
      {"--html folder cannot be written", "", "", "--resolution 33 --html /proc/view.html", 1,
       "cannot create a file in '/proc'", "check that the directory is writable", kOptionRun},
      {"--holes folder cannot be written", "", "", "--resolution 33 --holes /proc/holes.csv", 1,
       "cannot create a file in '/proc'", "check that the directory is writable", kOptionRun},
      {"output file name too long", "", "", "--resolution 33 -o " + std::string(250, 'a') + ".stl", 1,
       "file name is too long", "choose a shorter name", kOptionRun},
      {"-o is the --mesh input", "m.obj", tet_obj("10"), "--mesh FILE -o FILE", 2, "is the input file",
       "give -o another path"},
      {"--html is the --report", "", "", "--resolution 33 --html out.json", 2,
       "--report 'out.json' and --html 'out.json' are the same file", "give each output its own path",
       kOptionRun},
      {"--holes is the --report (another spelling)", "", "", "--resolution 33 --holes ./out.json", 2,
       "are the same file", "give each output its own path", kOptionRun},
  };
  return r;
}

class BadInputs : public ::testing::Test {
 protected:
  void SetUp() override {
    root_ = fs::temp_directory_path() / ("poreshell_test_bad_inputs_" + std::to_string(::getpid()));
    fs::remove_all(root_);
    fs::create_directories(root_ / "in" / "folder.stl");
    fs::create_directories(root_ / "out");
  }
  void TearDown() override {
    std::error_code ignored;
    fs::remove_all(root_, ignored);
  }
  fs::path root_;
};

TEST_F(BadInputs, EachRowFailsWithOneErrorLineNamingProblemAndFixAndWritesNothing) {
  for (const Row& row : rows()) {
    SCOPED_TRACE(row.name);
    const fs::path in = root_ / "in", out = root_ / "out";
    std::string args = row.args;
    const auto replace_all = [&](const std::string& from, const std::string& to) {
      for (std::size_t at = args.find(from); at != std::string::npos; at = args.find(from, at + to.size()))
        args.replace(at, from.size(), to);
    };
    if (!row.file.empty()) {
      std::ofstream(in / row.file, std::ios::binary) << row.content;
      replace_all("FILE", quoted(in / row.file));
    }
    replace_all("FOLDER", quoted(in / "folder.stl"));
    // "no output" asks for no file at all: a report alone would be an output.
    const bool no_output = row.name == "no output";
    if (args.find(" -o ") == std::string::npos && !no_output) args += " -o out.stl";
    const std::string command = args + " " + row.run + (no_output ? "" : " --report out.json");
    const auto run = run_program(PORESHELL_EXE, command, out, root_);
    const int status = run.status;
    ASSERT_TRUE(WIFEXITED(status)) << "killed by a signal: " << command;
    EXPECT_EQ(WEXITSTATUS(status), row.exit_code);
    const auto err = lines(run.err);
    ASSERT_EQ(err.size(), 1u) << run.err;
    EXPECT_EQ(err[0].rfind("poreshell: error: ", 0), 0u) << err[0];
    EXPECT_NE(err[0].find(row.problem), std::string::npos) << err[0];
    EXPECT_NE(err[0].find(row.fix), std::string::npos) << err[0];
    EXPECT_TRUE(fs::is_empty(out)) << "output left behind";
    if (!row.file.empty()) fs::remove(in / row.file);
  }
}

// Issue 47: two outputs naming one file (by any spelling), or -o naming the input, are refused before
// the run; nothing is written and the input is left as it was.
TEST_F(BadInputs, OutputsNamingOneFileOrTheInputAreRefusedBeforeTheRun) {
  const fs::path input = root_ / "in" / "keep.obj";
  std::ofstream(input) << tet_obj("10");
  const std::string in = quoted(input);
  const std::vector<std::string> cases = {"-o same.stl --report same.stl",
                                          "-o same.stl --html ./same.stl",
                                          "-o same.stl --png ../out/same.stl",
                                          "--report r.json --holes r.json",
                                          "-o " + in + " --report r.json",
                                          "-o out.stl --report " + in,
                                          "-o out.stl --iso 0.1,0.2 --html out-iso0.2.stl"};
  for (const std::string& outputs : cases) {
    SCOPED_TRACE(outputs);
    const std::string command = "--mesh " + in + " " + outputs + " " + kSmallRun;
    const auto run = run_program(PORESHELL_EXE, command, root_ / "out", root_);
    const int status = run.status;
    ASSERT_TRUE(WIFEXITED(status)) << "killed by a signal: " << command;
    EXPECT_EQ(WEXITSTATUS(status), 2);
    const auto err = lines(run.err);
    ASSERT_EQ(err.size(), 1u) << run.err;
    EXPECT_TRUE(err[0].find("are the same file") != std::string::npos ||
                err[0].find("is the input file") != std::string::npos)
        << err[0];
    EXPECT_TRUE(fs::is_empty(root_ / "out")) << "output left behind";
    EXPECT_EQ(read_file(input), tet_obj("10")) << "the input was changed";
  }
}

// One triangle is a valid (open) surface, not a bad input: the run writes a closed plate.
TEST_F(BadInputs, OneTriangleIsAcceptedAndGivesAClosedPlate) {
  std::ofstream(root_ / "in" / "one.obj") << "v 0 0 0\nv 10 0 0\nv 0 10 0\nf 1 2 3\n";
  const int status =
      run_program(PORESHELL_EXE,
                  "--mesh " + quoted(root_ / "in" / "one.obj") + " " + kSmallRun + " -o plate.stl",
                  root_ / "out", root_)
          .status;
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 0);
  EXPECT_TRUE(fs::exists(root_ / "out" / "plate.stl"));
}

}  // namespace
