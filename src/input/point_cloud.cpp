#include "input/point_cloud.hpp"

#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>

#include <algorithm>
#include <cmath>
#include <queue>
#include <span>
#include <stdexcept>

#include "core/error.hpp"
#include "geometry/plane_fit.hpp"

namespace poreshell {

SplatSurface::SplatSurface(std::vector<Vec3> points, const SplatOptions& options)
    : points_(std::move(points)) {
  if (options.normal_neighbors < 3 || options.radius_neighbor < 1)
    throw InputError("splat fit: need at least 3 neighbours for a normal and 1 for a radius");
  const auto need = static_cast<std::size_t>(std::max(options.normal_neighbors, options.radius_neighbor + 1));
  if (points_.size() < need)
    throw InputError("the point cloud has " + std::to_string(points_.size()) + " points; at least " +
                     std::to_string(need) + " are needed to fit a surface to it");
  const PointTree plain(points_);
  normals_.resize(points_.size());
  radii_.resize(points_.size());
  tbb::parallel_for(std::size_t{0}, points_.size(), [&](std::size_t i) {
    const auto near = plain.k_nearest(points_[i], need);
    // Normal: the least-variance direction of the neighbourhood (PCA plane fit). Its sign is irrelevant
    // for an unsigned distance.
    const auto nk = static_cast<std::size_t>(options.normal_neighbors);
    normals_[i] = fit_plane(points_, std::span(near.data(), nk)).normal().normalized();
    // near[0] is the point itself (or a duplicate at distance 0).
    radii_[i] = (points_[near[static_cast<std::size_t>(options.radius_neighbor)]] - points_[i]).norm();
  });
  tree_.emplace(points_, radii_);
}

double SplatSurface::splat_distance(std::size_t i, const Vec3& x, Vec3* closest) const {
  const Vec3 q = x - points_[i];
  const double a = q.dot(normals_[i]);
  const Vec3 t = q - a * normals_[i];
  const double tn = t.norm();
  const double r = radii_[i];
  const Vec3 in_plane = tn > r ? t * (r / tn) : t;
  if (closest) *closest = points_[i] + in_plane;
  return (q - in_plane).norm();
}

double SplatSurface::distance(const Vec3& p) const {
  return tree_->closest(p, [&](std::size_t i) { return splat_distance(i, p, nullptr); }).second;
}

std::optional<Vec3> SplatSurface::closest_point(const Vec3& p) const {
  return distance_and_closest_point(p).closest_point;
}

SurfaceQuery SplatSurface::distance_and_closest_point(const Vec3& p) const {
  const auto [i, d] = tree_->closest(p, [&](std::size_t j) { return splat_distance(j, p, nullptr); });
  Vec3 cp;
  splat_distance(i, p, &cp);
  return {d, cp};
}

Box SplatSurface::bounds() const {
  Box box{points_.front(), points_.front()};
  for (std::size_t i = 0; i < points_.size(); ++i) {
    box.min = box.min.cwiseMin(points_[i] - Vec3::Constant(radii_[i]));
    box.max = box.max.cwiseMax(points_[i] + Vec3::Constant(radii_[i]));
  }
  return box;
}

}  // namespace poreshell
