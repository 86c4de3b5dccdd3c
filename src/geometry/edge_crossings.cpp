#include "geometry/edge_crossings.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <numbers>

namespace poreshell::kuhn {

double crossing(double va, double vb, double iso) {
  return std::clamp((iso - va) / (vb - va), kSnap, 1.0 - kSnap);
}

double crossing_of_max(std::span<const std::span<const double>> parts, std::size_t i, std::size_t j,
                       double iso, std::uint8_t* part, double* exact) {
  const auto cross = [&](double v0, double v1) { return (iso - v0) / (v1 - v0); };
  bool lower_inside = true;
  for (const auto& p : parts) lower_inside = lower_inside && p[i] < iso;
  double t = lower_inside ? 1.0 : 0.0;
  for (std::size_t k = 0; k < parts.size(); ++k) {
    const double v0 = parts[k][i], v1 = parts[k][j];
    // lower_inside: the part that leaves first; else the part that enters last
    const double t_k = lower_inside ? (v1 < iso ? 1.0 : cross(v0, v1)) : (v0 < iso ? 0.0 : cross(v0, v1));
    if (lower_inside ? t_k < t : t_k > t) {
      t = t_k;
      if (part) *part = static_cast<std::uint8_t>(k);
    }
  }
  if (exact) *exact = t;
  return std::clamp(t, kSnap, 1.0 - kSnap);
}

EdgeCrossing vertex_crossing(const FieldLookup& lookup, std::int64_t lower, std::int64_t upper, double iso) {
  if (!lookup.parts.empty()) {
    const auto i = lookup.position(lower), j = lookup.position(upper);
    double exact = 0.0;
    if (i && j) {
      const double t = crossing_of_max(lookup.parts, *i, *j, iso, nullptr, &exact);
      return {t, std::clamp(exact, 0.0, 1.0)};
    }
  }
  const double va = lookup.at(lower), vb = lookup.at(upper);
  return {crossing(va, vb, iso), std::clamp((iso - va) / (vb - va), 0.0, 1.0)};
}

Vec3 along_surface(const FieldLookup& lookup, const PaddedGrid& grid, std::int64_t lower, int bits,
                   const EdgeCrossing& c, const Vec3& at) {
  const std::int64_t near = c.exact < 0.5 ? lower : lower + grid.offset(bits);
  Vec3 gradient;
  for (int axis = 0; axis < 3; ++axis) {
    const std::int64_t step = grid.offset(1 << axis);
    gradient[axis] = lookup.at(near + step) - lookup.at(near - step);
  }
  const double length = gradient.norm();
  if (!(length > 0.0)) return at;
  const Vec3 n = gradient / length;
  const Vec3 exact = grid.index(lower) + c.exact * direction(bits);
  return at - n * n.dot(at - exact);
}

const Vec3& MovedCrossings::clamped_place(const TriangleMesh& mesh, std::size_t v) const {
  if (!moved[v]) return mesh.vertices[v];
  const auto it = std::lower_bound(vertices.begin(), vertices.end(), static_cast<std::int32_t>(v));
  return clamped[static_cast<std::size_t>(it - vertices.begin())];
}

void undo_moves_that_spoil_triangles(TriangleMesh& mesh, MovedCrossings& m) {
  const double least = std::pow(std::sin(kLeastAngleDegrees * std::numbers::pi / 180.0), 2);
  std::vector<char> undo(mesh.vertices.size(), 0);
  const auto spoiled = [&](const std::array<std::size_t, 3>& c) {
    const Vec3 &a = mesh.vertices[c[0]], &b = mesh.vertices[c[1]], &d = mesh.vertices[c[2]];
    const Vec3 normal = (b - a).cross(d - a);
    if (min_angle_sine_squared(a, b, d, normal) < least) return true;
    const Vec3 &ca = m.clamped_place(mesh, c[0]), &cb = m.clamped_place(mesh, c[1]),
               &cd = m.clamped_place(mesh, c[2]);
    return !(normal.dot((cb - ca).cross(cd - ca)) > 0.0);
  };
  for (bool any = true; any;) {
    any = tbb::parallel_reduce(
        tbb::blocked_range<std::size_t>(0, mesh.triangles.size(), 1 << 14), false,
        [&](const tbb::blocked_range<std::size_t>& r, bool found) {
          for (std::size_t f = r.begin(); f != r.end(); ++f) {
            std::array<std::size_t, 3> c;
            for (std::size_t k = 0; k < 3; ++k) c[k] = static_cast<std::size_t>(mesh.triangles[f][k]);
            if (!m.moved[c[0]] && !m.moved[c[1]] && !m.moved[c[2]]) continue;
            if (!spoiled(c)) continue;
            for (std::size_t v : c)
              if (m.moved[v]) undo[v] = 1;  // only ever set to 1: concurrent writes agree
            found = true;
          }
          return found;
        },
        std::logical_or<>());
    for (std::size_t k = 0; k < m.vertices.size(); ++k) {
      const auto v = static_cast<std::size_t>(m.vertices[k]);
      if (!undo[v]) continue;
      mesh.vertices[v] = m.clamped[k];
      m.moved[v] = 0;
      undo[v] = 0;
    }
  }
}

}  // namespace poreshell::kuhn
