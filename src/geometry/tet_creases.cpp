#include "geometry/tet_creases.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

namespace poreshell {
namespace {

double largest_cosine(const Vec3& a, const Vec3& b, const Vec3& c) {
  const auto cosine = [](const Vec3& p, const Vec3& q, const Vec3& r) {
    const Vec3 u = q - p, w = r - p;
    const double n = u.norm() * w.norm();
    return n > 0.0 ? u.dot(w) / n : 1.0;
  };
  return std::max({cosine(a, b, c), cosine(b, c, a), cosine(c, a, b)});
}

// Fans a convex polygon (indices, counter-clockwise) from the corner whose fan has the largest smallest
// angle, or from its first corner.
void fan(const std::vector<int>& polygon, const std::vector<Vec3>& position,
         std::vector<std::array<int, 3>>& out, bool from_first = false) {
  const std::size_t n = polygon.size();
  if (n < 3) return;
  const auto at = [&](std::size_t i) { return position[static_cast<std::size_t>(polygon[i % n])]; };
  std::size_t best = 0;
  double best_cosine = 2.0;
  for (std::size_t s = 0; s < n && n > 3 && !from_first; ++s) {
    double worst = -1.0;
    for (std::size_t i = 1; i + 1 < n; ++i)
      worst = std::max(worst, largest_cosine(at(s), at(s + i), at(s + i + 1)));
    if (worst < best_cosine) {
      best_cosine = worst;
      best = s;
    }
  }
  for (std::size_t i = 1; i + 1 < n; ++i)
    out.push_back({polygon[best], polygon[(best + i) % n], polygon[(best + i + 1) % n]});
}

}  // namespace

void split_at_creases(std::span<const PatchCorner> corners, const Vec3* inside,
                      std::vector<std::array<int, 3>>& out) {
  const int n = static_cast<int>(corners.size());
  thread_local std::vector<Vec3> position;  // the corners' and `inside`
  thread_local std::vector<int> creases, piece;
  position.clear();
  creases.clear();
  for (int i = 0; i < n; ++i) {
    position.push_back(corners[static_cast<std::size_t>(i)].position);
    if (corners[static_cast<std::size_t>(i)].part == kOnCrease) creases.push_back(i);
  }
  position.push_back(inside ? *inside : Vec3::Zero());
  const auto run = [&](int from, int to) -> std::vector<int>& {  // from..to inclusive, counter-clockwise
    piece.clear();
    for (int i = from;; i = (i + 1) % n) {
      piece.push_back(i);
      if (i == to) break;
    }
    return piece;
  };
  if (creases.size() == 2) {
    fan(run(creases[0], creases[1]), position, out);
    fan(run(creases[1], creases[0]), position, out);
  } else if (creases.size() == 3 && inside) {
    for (std::size_t c = 0; c < 3; ++c) {
      run(creases[c], creases[(c + 1) % 3]).push_back(n);
      fan(piece, position, out);
    }
  } else if (!creases.empty()) {
    // From a crease point: a triangle of its two neighbours and itself would lie in the tetrahedron's
    // face, as the neighbouring tetrahedron's would, back to back.
    fan(run(creases[0], (creases[0] + n - 1) % n), position, out, true);
  } else {
    fan(run(0, n - 1), position, out);
  }
}

std::optional<std::array<double, 3>> face_crease_weights(std::span<const std::array<double, 3>> values,
                                                         std::size_t i, std::size_t j, double iso,
                                                         double snap) {
  Eigen::Matrix3d m;
  m << values[i][0], values[i][1], values[i][2], values[j][0], values[j][1], values[j][2], 1.0, 1.0, 1.0;
  const Eigen::Vector3d w = m.partialPivLu().solve(Eigen::Vector3d(iso, iso, 1.0));
  if (!(w.minCoeff() >= snap)) return std::nullopt;  // NaN too
  return std::array<double, 3>{w(0), w(1), w(2)};
}

std::optional<std::array<double, 4>> inside_crease_weights(std::span<const std::array<double, 4>> values,
                                                           double iso, double snap) {
  Eigen::Matrix4d m;
  for (std::size_t k = 0; k < 3; ++k)
    for (std::size_t c = 0; c < 4; ++c)
      m(static_cast<Eigen::Index>(k), static_cast<Eigen::Index>(c)) = values[k][c];
  m.row(3).setOnes();
  const Eigen::Vector4d w = m.partialPivLu().solve(Eigen::Vector4d(iso, iso, iso, 1.0));
  if (!(w.minCoeff() >= snap)) return std::nullopt;  // outside the tetrahedron, or NaN
  return std::array<double, 4>{w(0), w(1), w(2), w(3)};
}

}  // namespace poreshell
