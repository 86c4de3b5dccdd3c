// The public API in 20 lines: a mesh made in memory, perforated with 8 mm holes, checked and saved.
// Build against the installed library: c++ -std=c++20 perforate_sphere.cpp -lporeshell

#include <poreshell/poreshell.hpp>

#include <cmath>
#include <cstdio>

int main() {
  poreshell::MeshInput input;  // an octahedron refined and pushed onto a sphere of radius 40 mm
  input.mesh.vertices = {{40, 0, 0}, {-40, 0, 0}, {0, 40, 0}, {0, -40, 0}, {0, 0, 40}, {0, 0, -40}};
  input.mesh.triangles = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4}, {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
  for (int level = 0; level < 5; ++level) {
    poreshell::Mesh finer{input.mesh.vertices, {}};
    for (const auto& t : input.mesh.triangles) {
      std::int32_t mid[3];
      for (int e = 0; e < 3; ++e) {
        const auto &a = input.mesh.vertices[t[e]], &b = input.mesh.vertices[t[(e + 1) % 3]];
        poreshell::Point m{a[0] + b[0], a[1] + b[1], a[2] + b[2]};
        const double scale = 40.0 / std::sqrt(m[0] * m[0] + m[1] * m[1] + m[2] * m[2]);
        for (double& x : m) x *= scale;
        mid[e] = static_cast<std::int32_t>(finer.vertices.size());
        finer.vertices.push_back(m);  // duplicates at shared edges are welded by the library
      }
      finer.triangles.push_back({t[0], mid[0], mid[2]});
      finer.triangles.push_back({mid[0], t[1], mid[1]});
      finer.triangles.push_back({mid[2], mid[1], t[2]});
      finer.triangles.push_back({mid[0], mid[1], mid[2]});
    }
    input.mesh = finer;
  }
  poreshell::Options options;
  options.hole_diameter = 8.0;  // mm
  options.spacing = 14.0;
  options.wall = 2.0;
  try {
    const poreshell::Result result = poreshell::perforate(input, options);
    const poreshell::LevelReport& level = result.report.outputs.at(0);
    std::printf("%zu triangles, %s, %lld pores\n", result.outputs[0].mesh.triangles.size(),
                level.topology.closed && level.topology.manifold ? "closed and manifold" : "NOT printable",
                static_cast<long long>(level.pores_from_euler));
    poreshell::save_mesh("sphere.stl", result.outputs[0].mesh);
    return level.topology.closed && level.pores_from_euler > 10 ? 0 : 1;
  } catch (const poreshell::Error& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
}
