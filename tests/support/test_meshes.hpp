#pragma once
// Meshes several tests build, as the public API's Mesh (mm, outward, counter-clockwise seen from outside).

#include <cmath>
#include <cstdint>
#include <numbers>

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

}  // namespace poreshell::test_support
