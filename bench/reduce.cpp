// The triangle reduction's cost (issue 18, item 8; docs/benchmarks.md "Triangle reduction").
//
//   bench_reduce MESH --triangles N [--distance D] [--repeats 3]
//
// Reads a closed mesh (an unreduced poreshell output, in its own units) and reduces it to N
// triangles within D, timing decimate_mesh() alone. Prints per repeat the wall time, the
// microseconds per collapse made, the count reached, the distance measured and a hash of the kept
// triangles' corners (their x coordinates, in order), the same on every repeat, to compare builds.

#include <fmt/core.h>

#include <CLI/CLI.hpp>
#include <chrono>
#include <cstdint>
#include <functional>
#include <string>

#include "io/mesh_io.hpp"
#include "shell/mesh_decimate.hpp"

int main(int argc, char** argv) {
  using namespace poreshell;
  CLI::App app("poreshell triangle reduction benchmark");
  std::string path;
  std::int64_t triangles = 0;
  double distance = 0.05;
  int repeats = 3;
  app.add_option("mesh", path, "closed mesh file")->required();
  app.add_option("--triangles", triangles, "target triangle count")->required();
  app.add_option("--distance", distance, "distance bound, in the mesh's units");
  app.add_option("--repeats", repeats, "runs");
  CLI11_PARSE(app, argc, argv);

  const TriangleMesh input = read_triangle_mesh(path);
  for (int r = 0; r < repeats; ++r) {
    TriangleMesh mesh = input;
    DecimateOptions options;
    options.max_triangles = triangles;
    options.max_distance = distance;
    const auto start = std::chrono::steady_clock::now();
    const DecimateResult result = decimate_mesh(mesh, options);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const double collapses = static_cast<double>(result.triangles_before - result.triangles_after) / 2.0;
    std::size_t hash = 0;
    for (const auto& t : mesh.triangles)
      for (const std::int32_t v : t)
        hash = hash * 1000003u ^ std::hash<double>{}(mesh.vertices[static_cast<std::size_t>(v)].x());
    fmt::print("{} -> {} triangles in {:.2f} s, {:.1f} us a collapse, distance {:.4f}, output hash {:x}\n",
               result.triangles_before, result.triangles_after, seconds, 1e6 * seconds / collapses,
               result.max_distance, hash);
  }
}
