#pragma once
// Point clouds as surfaces without a PDE (the default "direct" route): each point carries a small disc
// (a splat) in its tangent plane, fitted to its nearest neighbours, and the surface is the union of the
// discs. Distance to a union of sets is the minimum of the distances to each, so it is exactly
// 1-Lipschitz (as the band builder's block culling needs), and the closest point is the closest point
// on the nearest disc. A spatial tree over the points answers nearest-neighbour and disc queries.

#include <cstdint>
#include <limits>
#include <optional>
#include <span>
#include <utility>
#include <vector>

#include "geometry/point_tree.hpp"
#include "geometry/surface.hpp"

namespace poreshell {

struct SplatOptions {
  int normal_neighbors = 10;  // points in the plane fit (PCA) of each splat's normal
  int radius_neighbor = 2;    // splat radius = distance to this nearest neighbour (docs/point-clouds.md)
};

class SplatSurface final : public Surface {
 public:
  // Throws InputError if there are fewer points than a plane fit needs.
  explicit SplatSurface(std::vector<Vec3> points, const SplatOptions& options = {});

  double distance(const Vec3& p) const override;  // unsigned
  std::optional<Vec3> closest_point(const Vec3& p) const override;
  bool closest_point_is_exact() const override { return true; }
  SurfaceQuery distance_and_closest_point(const Vec3& p) const override;  // one search
  Box bounds() const override;
  std::string name() const override { return "point splats"; }

  std::size_t size() const { return points_.size(); }
  std::span<const Vec3> points() const { return points_; }
  std::span<const Vec3> normals() const { return normals_; }  // unit, of either side
  std::span<const double> radii() const { return radii_; }
  const Vec3& normal(std::size_t i) const { return normals_[i]; }
  double radius(std::size_t i) const { return radii_[i]; }

 private:
  // Distance from x to splat i, and its closest point.
  double splat_distance(std::size_t i, const Vec3& x, Vec3* closest) const;

  std::vector<Vec3> points_, normals_;
  std::vector<double> radii_;
  std::optional<PointTree> tree_;
};

}  // namespace poreshell
