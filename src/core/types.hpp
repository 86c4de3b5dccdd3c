#pragma once
// Small vocabulary types shared by every stage of the pipeline.

#include <Eigen/Core>
#include <array>
#include <cstdint>

namespace poreshell {

using Vec3 = Eigen::Vector3d;

// A point of the public API (poreshell::Point, three doubles) as the stages' vector.
inline Vec3 vec(const std::array<double, 3>& p) {
  return {p[0], p[1], p[2]};
}

// Integer grid coordinate (i, j, k), zero-based along x, y, z.
struct Coord {
  std::int32_t i = 0, j = 0, k = 0;
  friend bool operator==(const Coord&, const Coord&) = default;
};

struct Box {
  Vec3 min = Vec3::Zero();
  Vec3 max = Vec3::Zero();
};

}  // namespace poreshell
