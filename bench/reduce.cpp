// The triangle reduction's cost (issue 18, item 8; docs/benchmarks-history.md "Triangle reduction").
//
//   bench_reduce MESH --triangles N [--distance D] [--repeats 3] [--compare] [--bound-only]
//
// Reads a closed mesh (an unreduced poreshell output, in its own units) and reduces it to N
// triangles within D, timing decimate_mesh() alone. Prints per repeat the wall time, the
// microseconds per collapse made, the count reached, the distance measured, how many collapses the
// fans' own bounds settled and how many the checks against the original, and a hash of the kept
// triangles' corners (their x coordinates, in order), the same on every repeat, to compare builds,
// and the triangles' shapes (the smallest angle, how many under 10 degrees).
// --compare alternates the default rule with the checks alone and prints the ratio of the fastest
// of each.

#include <fmt/core.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <numbers>
#include <string>

#include "geometry/mesh.hpp"
#include "io/mesh_io.hpp"
#include "io/mesh_writers.hpp"
#include "reduce/collapse_bounds.hpp"
#include "reduce/mesh_decimate.hpp"

int main(int argc, char** argv) {
  using namespace poreshell;
  CLI::App app("poreshell triangle reduction benchmark");
  std::string path, output;
  std::int64_t triangles = 0;
  double distance = 0.05;
  int repeats = 3;
  bool compare = false, bound_only = false, placed = false;
  app.add_option("mesh", path, "closed mesh file")->required();
  app.add_option("--triangles", triangles, "target triangle count")->required();
  app.add_option("--distance", distance, "distance bound, in the mesh's units");
  app.add_option("--repeats", repeats, "runs");
  app.add_option("--output", output, "write the last run's reduced mesh here");
  app.add_flag("--compare", compare, "also time the checks alone (no bounds from the fans)");
  app.add_flag("--placed", placed, "collapses that place the kept vertex (placed_collapse.hpp)");
  app.add_flag("--bound-only", bound_only,
               "the fans' bounds alone, as the default output reduces (issue 49)");
  CLI11_PARSE(app, argc, argv);

  const TriangleMesh input = read_triangle_mesh(path);
  double fastest[2] = {std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity()};
  for (int run = 0; run < (compare ? 2 : 1) * repeats; ++run) {
    const bool checks_alone = compare && run % 2 == 1;
    TriangleMesh mesh = input;
    DecimateOptions options;
    options.max_triangles = triangles;
    options.max_distance = distance;
    options.rule = placed         ? DistanceRule::kPlaced
                   : checks_alone ? DistanceRule::kCheckOnly
                   : bound_only   ? DistanceRule::kBoundOnly
                                  : DistanceRule::kBoundOrCheck;
    const auto start = std::chrono::steady_clock::now();
    const DecimateResult result = decimate_mesh(mesh, options);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const double collapses = static_cast<double>(result.triangles_before - result.triangles_after) / 2.0;
    std::size_t hash = 0;
    for (const auto& t : mesh.triangles)
      for (const std::int32_t v : t)
        hash = hash * 1000003u ^ std::hash<double>{}(mesh.vertices[static_cast<std::size_t>(v)].x());
    fastest[checks_alone] = std::min(fastest[checks_alone], seconds);
    if (!output.empty()) write_mesh(output, mesh);
    fmt::print("{}{} -> {} triangles in {:.2f} s, {:.1f} us a collapse, distance {:.4f}, ",
               checks_alone ? "checks alone: " : "", result.triangles_before, result.triangles_after, seconds,
               1e6 * seconds / collapses, result.max_distance);
    // The shapes, which the collapses' order changes (the rules hold them above 10 degrees but where
    // they replace a sharper triangle): the smallest angle, and how many triangles have one under 10.
    const double least = analyze_topology(mesh).min_angle_degrees;
    const double sine_10 = std::sin(10.0 * std::numbers::pi / 180.0);
    std::int64_t under_10 = 0;
    for (const auto& t : mesh.triangles)
      under_10 += min_angle_sine_squared(mesh.vertices[t[0]], mesh.vertices[t[1]], mesh.vertices[t[2]]) <
                  sine_10 * sine_10;
    fmt::print("smallest angle {:.2f} deg, {} under 10 deg, ", least, under_10);
    fmt::print("sampled reduced->full {:.4f} full->reduced {:.4f}, attempts {}, ",
               result.sampled.reduced_to_full, result.sampled.full_to_reduced, result.attempts);
    fmt::print("collapses bounded {} checked {}, output hash {:x}\n", result.collapses.bounded,
               result.collapses.checked, hash);
  }
  if (compare) fmt::print("fastest with bounds / checks alone: {:.2f}\n", fastest[0] / fastest[1]);
}
