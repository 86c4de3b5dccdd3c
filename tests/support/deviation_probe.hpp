#pragma once
// An independent two-sided distance between two triangle meshes, for the tests of the reduction
// (issue 49): points sampled by area on each mesh from std::mt19937_64, each one's distance to the
// other mesh's triangles by Ericson's point-to-triangle (Real-Time Collision Detection, 5.1.5) over a
// uniform grid of triangle boxes. Shares no code with the library's MeshSurface or its reduction.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <random>
#include <unordered_map>
#include <vector>

#include "poreshell/geometry.hpp"

namespace poreshell::test_support {

struct P3 {
  double x, y, z;
};
inline P3 operator-(P3 a, P3 b) {
  return {a.x - b.x, a.y - b.y, a.z - b.z};
}
inline P3 operator+(P3 a, P3 b) {
  return {a.x + b.x, a.y + b.y, a.z + b.z};
}
inline P3 operator*(double s, P3 a) {
  return {s * a.x, s * a.y, s * a.z};
}
inline double dot(P3 a, P3 b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}
inline P3 cross(P3 a, P3 b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}

// Closest point on triangle abc to p (Ericson 5.1.5), by Voronoi regions.
inline P3 closest_on_triangle(P3 p, P3 a, P3 b, P3 c) {
  const P3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = dot(ab, ap), d2 = dot(ac, ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const P3 bp = p - b;
  const double d3 = dot(ab, bp), d4 = dot(ac, bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + (d1 / (d1 - d3)) * ab;
  const P3 cp = p - c;
  const double d5 = dot(ab, cp), d6 = dot(ac, cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + (d2 / (d2 - d6)) * ac;
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) return b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b);
  const double denom = va + vb + vc;
  if (!(std::abs(denom) > 0)) return a;  // degenerate: its corners stand for it
  return a + (vb / denom) * ab + (vc / denom) * ac;
}

// Distances up to `reach` from points to a mesh: triangles bucketed by their boxes on a grid of cell
// `reach`, so a point looks at the 27 cells around it. A point with no triangle within reach gets reach.
class TriangleGrid {
 public:
  TriangleGrid(const Mesh& mesh, double reach) : mesh_(mesh), reach_(reach) {
    for (std::size_t f = 0; f < mesh.triangles.size(); ++f) {
      std::array<std::int64_t, 3> lo{}, hi{};
      for (int k = 0; k < 3; ++k) {
        double mn = 1e300, mx = -1e300;
        for (int i = 0; i < 3; ++i) {
          const double v = mesh.vertices[static_cast<std::size_t>(mesh.triangles[f][i])][k];
          mn = std::min(mn, v);
          mx = std::max(mx, v);
        }
        lo[k] = cell(mn);
        hi[k] = cell(mx);
      }
      for (std::int64_t i = lo[0]; i <= hi[0]; ++i)
        for (std::int64_t j = lo[1]; j <= hi[1]; ++j)
          for (std::int64_t k = lo[2]; k <= hi[2]; ++k) cells_[key(i, j, k)].push_back(f);
    }
  }
  double distance(P3 p) const {
    double best = reach_;
    const std::int64_t ci = cell(p.x), cj = cell(p.y), ck = cell(p.z);
    for (std::int64_t i = ci - 1; i <= ci + 1; ++i)
      for (std::int64_t j = cj - 1; j <= cj + 1; ++j)
        for (std::int64_t k = ck - 1; k <= ck + 1; ++k) {
          const auto it = cells_.find(key(i, j, k));
          if (it == cells_.end()) continue;
          for (const std::size_t f : it->second) {
            const P3 q = closest_on_triangle(p, vertex(f, 0), vertex(f, 1), vertex(f, 2));
            best = std::min(best, std::sqrt(dot(q - p, q - p)));
          }
        }
    return best;
  }
  P3 vertex(std::size_t f, int i) const {
    const auto& v = mesh_.vertices[static_cast<std::size_t>(mesh_.triangles[f][i])];
    return {v[0], v[1], v[2]};
  }

 private:
  std::int64_t cell(double x) const { return static_cast<std::int64_t>(std::floor(x / reach_)); }
  static std::int64_t key(std::int64_t i, std::int64_t j, std::int64_t k) {
    return ((i + (1 << 20)) << 42) | ((j + (1 << 20)) << 21) | (k + (1 << 20));
  }
  const Mesh& mesh_;
  double reach_;
  std::unordered_map<std::int64_t, std::vector<std::size_t>> cells_;
};

// Points by area on `mesh`.
inline std::vector<P3> sample_by_area(const Mesh& mesh, int count, std::uint64_t seed) {
  const TriangleGrid view(mesh, 1.0);
  std::vector<double> area;
  for (std::size_t f = 0; f < mesh.triangles.size(); ++f) {
    const P3 a = view.vertex(f, 0), b = view.vertex(f, 1), c = view.vertex(f, 2);
    const P3 n = cross(b - a, c - a);
    area.push_back(0.5 * std::sqrt(dot(n, n)));
  }
  std::mt19937_64 random(seed);
  std::discrete_distribution<std::size_t> pick(area.begin(), area.end());
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<P3> points;
  for (int i = 0; i < count; ++i) {
    const std::size_t f = pick(random);
    double u = unit(random), v = unit(random);
    if (u + v > 1) u = 1 - u, v = 1 - v;
    const P3 a = view.vertex(f, 0), b = view.vertex(f, 1), c = view.vertex(f, 2);
    points.push_back(a + u * (b - a) + v * (c - a));
  }
  return points;
}

// The largest distance found from `count` points on each mesh to the other, up to `reach`.
inline double sampled_two_sided_distance(const Mesh& a, const Mesh& b, int count, double reach,
                                         std::uint64_t seed = 7) {
  double worst = 0.0;
  const TriangleGrid grid_a(a, reach), grid_b(b, reach);
  for (const P3& p : sample_by_area(a, count, seed)) worst = std::max(worst, grid_b.distance(p));
  for (const P3& p : sample_by_area(b, count, seed + 1)) worst = std::max(worst, grid_a.distance(p));
  return worst;
}

}  // namespace poreshell::test_support
