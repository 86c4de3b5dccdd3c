#include "geometry/plane_fit.hpp"

#include <Eigen/Eigenvalues>

namespace poreshell {
namespace {

template <class At>
PlaneFit fit(std::size_t n, At&& at) {
  PlaneFit f;
  if (n == 0) return f;
  for (std::size_t i = 0; i < n; ++i) f.centroid += at(i);
  f.centroid /= static_cast<double>(n);
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3 d = at(i) - f.centroid;
    cov += d * d.transpose();
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov);
  f.variances = eig.eigenvalues();
  f.axes = eig.eigenvectors();
  return f;
}

}  // namespace

PlaneFit fit_plane(std::span<const Vec3> points) {
  return fit(points.size(), [&](std::size_t i) -> const Vec3& { return points[i]; });
}

PlaneFit fit_plane(const std::vector<Vec3>& points, std::span<const std::size_t> indices) {
  return fit(indices.size(), [&](std::size_t i) -> const Vec3& { return points[indices[i]]; });
}

}  // namespace poreshell
