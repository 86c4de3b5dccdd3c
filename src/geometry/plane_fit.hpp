#pragma once
// Best-fit plane of a set of points by principal component analysis: the splats' normals, the umbrellas'
// and hole caps' tangent planes, the collinearity check.

#include <cstddef>
#include <span>
#include <vector>

#include "core/types.hpp"

namespace poreshell {

struct PlaneFit {
  Vec3 centroid = Vec3::Zero();
  Vec3 variances = Vec3::Zero();  // of the points along the axes, ascending (times the count)
  Eigen::Matrix3d axes =
      Eigen::Matrix3d::Identity();  // unit columns, by ascending variance: col(0) is the plane's normal

  Vec3 normal() const { return axes.col(0); }
  // In the plane: the direction of largest spread, and the one across it.
  Vec3 major() const { return axes.col(2); }
  Vec3 minor() const { return axes.col(1); }
};

PlaneFit fit_plane(std::span<const Vec3> points);
// The points points[i] for i in `indices`.
PlaneFit fit_plane(const std::vector<Vec3>& points, std::span<const std::size_t> indices);

}  // namespace poreshell
