#include "test_meshes.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <map>
#include <numbers>
#include <utility>

namespace poreshell::test_support {

Mesh open_sleeve(double radius, double length, int segments, int rings) {
  Mesh m;
  for (int r = 0; r <= rings; ++r)
    for (int s = 0; s < segments; ++s) {
      const double a = 2 * std::numbers::pi * s / segments;
      m.vertices.push_back({radius * std::cos(a), radius * std::sin(a), length * r / rings});
    }
  const auto at = [&](int r, int s) { return static_cast<std::int32_t>(r * segments + s % segments); };
  for (int r = 0; r < rings; ++r)
    for (int s = 0; s < segments; ++s) {
      m.triangles.push_back({at(r, s), at(r, s + 1), at(r + 1, s + 1)});
      m.triangles.push_back({at(r, s), at(r + 1, s + 1), at(r + 1, s)});
    }
  return m;
}

Mesh revolve(const std::vector<std::array<double, 2>>& profile, int segments) {
  Mesh m;
  const int n = static_cast<int>(profile.size());
  m.vertices.push_back({0, 0, profile.front()[1]});
  for (int k = 1; k + 1 < n; ++k)
    for (int s = 0; s < segments; ++s) {
      const double a = 2 * std::numbers::pi * s / segments;
      m.vertices.push_back({profile[k][0] * std::cos(a), profile[k][0] * std::sin(a), profile[k][1]});
    }
  const auto top = static_cast<std::int32_t>(m.vertices.size());
  m.vertices.push_back({0, 0, profile.back()[1]});
  const auto at = [&](int k, int s) {
    return static_cast<std::int32_t>(1 + (k - 1) * segments + s % segments);
  };
  for (int s = 0; s < segments; ++s) {
    m.triangles.push_back({0, at(1, s + 1), at(1, s)});
    for (int k = 1; k + 2 < n; ++k) {
      m.triangles.push_back({at(k, s), at(k, s + 1), at(k + 1, s + 1)});
      m.triangles.push_back({at(k, s), at(k + 1, s + 1), at(k + 1, s)});
    }
    m.triangles.push_back({at(n - 2, s), at(n - 2, s + 1), top});
  }
  return m;
}

namespace {

Point times(double r, const Vec3& unit) {
  const Vec3 p = r * unit;
  return {p.x(), p.y(), p.z()};
}

}  // namespace

Mesh uv_sphere(double r, int rings, int segments) {
  Mesh m;
  m.vertices.push_back({0, 0, r});
  for (int i = 1; i < rings; ++i)
    for (int j = 0; j < segments; ++j) {
      const double theta = std::numbers::pi * i / rings, phi = 2 * std::numbers::pi * j / segments;
      m.vertices.push_back(
          times(r, Vec3(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta))));
    }
  m.vertices.push_back({0, 0, -r});
  const auto at = [&](int ring, int j) {
    return static_cast<std::int32_t>(1 + (ring - 1) * segments + j % segments);
  };
  const auto south = static_cast<std::int32_t>(m.vertices.size() - 1);
  for (int j = 0; j < segments; ++j) {
    m.triangles.push_back({0, at(1, j), at(1, j + 1)});
    for (int i = 1; i + 1 < rings; ++i) {
      m.triangles.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
      m.triangles.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
    }
    m.triangles.push_back({at(rings - 1, j), south, at(rings - 1, j + 1)});
  }
  return m;
}

Mesh upper_hemisphere(double r, int rings, int segments) {
  Mesh m;
  m.vertices.push_back({0, 0, r});
  for (int i = 1; i <= rings; ++i) {
    const double theta = 0.5 * std::numbers::pi * i / rings;
    for (int j = 0; j < segments; ++j) {
      const double phi = 2.0 * std::numbers::pi * j / segments;
      const double z = i == rings ? 0.0 : std::cos(theta);
      m.vertices.push_back(
          times(r, Vec3(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), z)));
    }
  }
  const auto ring = [&](int i, int j) {
    return static_cast<std::int32_t>(1 + (i - 1) * segments + j % segments);
  };
  for (int j = 0; j < segments; ++j) m.triangles.push_back({0, ring(1, j), ring(1, j + 1)});
  for (int i = 1; i < rings; ++i)
    for (int j = 0; j < segments; ++j) {
      m.triangles.push_back({ring(i, j), ring(i + 1, j), ring(i + 1, j + 1)});
      m.triangles.push_back({ring(i, j), ring(i + 1, j + 1), ring(i, j + 1)});
    }
  return m;
}

Mesh square_sheet(double lo, double side, int n, double z) {
  Mesh m;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) m.vertices.push_back({lo + side * i / n, lo + side * j / n, z});
  const auto at = [n](int i, int j) { return static_cast<std::int32_t>(i + (n + 1) * j); };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      m.triangles.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
      m.triangles.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
    }
  return m;
}

TriangleMesh icosphere(int subdivisions, const Vec3& center, double radius) {
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  TriangleMesh m;
  m.vertices = {{-1, t, 0},  {1, t, 0},  {-1, -t, 0}, {1, -t, 0}, {0, -1, t},  {0, 1, t},
                {0, -1, -t}, {0, 1, -t}, {t, 0, -1},  {t, 0, 1},  {-t, 0, -1}, {-t, 0, 1}};
  for (Vec3& v : m.vertices) v.normalize();
  m.triangles = {{0, 11, 5},  {0, 5, 1},  {0, 1, 7},  {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
                 {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
                 {3, 8, 9},   {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
  for (int s = 0; s < subdivisions; ++s) {
    std::map<std::pair<std::int32_t, std::int32_t>, std::int32_t> midpoint;
    const auto mid = [&](std::int32_t a, std::int32_t b) {
      const auto [it, added] =
          midpoint.try_emplace(std::minmax(a, b), static_cast<std::int32_t>(m.vertices.size()));
      if (added) m.vertices.push_back((m.vertices[a] + m.vertices[b]).normalized());
      return it->second;
    };
    std::vector<std::array<std::int32_t, 3>> finer;
    for (const auto& [a, b, c] : m.triangles) {
      const std::int32_t ab = mid(a, b), bc = mid(b, c), ca = mid(c, a);
      finer.insert(finer.end(), {{a, ab, ca}, {b, bc, ab}, {c, ca, bc}, {ab, bc, ca}});
    }
    m.triangles = std::move(finer);
  }
  for (Vec3& v : m.vertices) v = center + radius * v;
  return m;
}

Mesh inverted(Mesh mesh) {
  for (auto& t : mesh.triangles) std::swap(t[1], t[2]);
  return mesh;
}

void append(TriangleMesh& to, const Mesh& mesh, const Vec3& shift) {
  const auto base = static_cast<std::int32_t>(to.vertices.size());
  for (const Point& p : mesh.vertices) to.vertices.push_back(shift + Vec3(p[0], p[1], p[2]));
  for (const auto& t : mesh.triangles) to.triangles.push_back({base + t[0], base + t[1], base + t[2]});
}

TriangleMesh to_triangle_mesh(const Mesh& mesh, const Vec3& shift) {
  TriangleMesh m;
  append(m, mesh, shift);
  return m;
}

void write_obj_text(const std::filesystem::path& path, const Mesh& mesh) {
  std::ofstream out(path);
  for (const Point& p : mesh.vertices) out << "v " << p[0] << ' ' << p[1] << ' ' << p[2] << '\n';
  for (const auto& t : mesh.triangles)  // OBJ counts from 1
    out << "f " << t[0] + 1 << ' ' << t[1] + 1 << ' ' << t[2] + 1 << '\n';
}

}  // namespace poreshell::test_support
