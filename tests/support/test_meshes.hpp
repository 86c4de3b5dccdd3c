#pragma once
// Meshes several tests build, as the public API's Mesh (mm, outward, counter-clockwise seen from outside).

#include <array>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <vector>

#include "poreshell/geometry.hpp"

namespace poreshell::test_support {

// An open cylinder (a sleeve, no caps) about the z axis from z = 0 to `length`, normals outward:
// `segments` around and `rings` bands along, two boundary circles.
inline Mesh open_sleeve(double radius, double length, int segments = 96, int rings = 40) {
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

// A closed surface of revolution about z from a profile of (rho, z) that starts and ends on the axis,
// outward when the profile runs from bottom to top.
inline Mesh revolve(const std::vector<std::array<double, 2>>& profile, int segments) {
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

}  // namespace poreshell::test_support
