#include "measure/hole_table.hpp"

// The table from each seed's hole (hole_cut.cpp): seeds cut aslant cut again from their loop's centre,
// a hole met by two seeds kept once, each hole's nearest neighbour; and the wall's middle of a surface.

#include <tbb/parallel_for.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <optional>
#include <utility>
#include <vector>

#include "band/band.hpp"
#include "geometry/point_tree.hpp"
#include "measure/hole_cut.hpp"

namespace poreshell {

HoleTable measure_holes(const TriangleMesh& mesh, std::span<const HoleSeed> seeds, const MidWall* mid_wall) {
  std::vector<std::optional<HoleRecord>> cut = cut_holes(mesh, seeds, mid_wall);
  // A seed well off its loop's centre cut the hole aslant: cut again from the centre.
  if (mid_wall) {
    std::vector<std::size_t> which;
    for (std::size_t s = 0; s < seeds.size(); ++s)
      if (cut[s] && (cut[s]->centre - seeds[s].point).norm() > 0.05 * cut[s]->diameter) which.push_back(s);
    std::vector<std::optional<HoleSeed>> moved(which.size());
    tbb::parallel_for(std::size_t{0}, which.size(),
                      [&](std::size_t i) { moved[i] = mid_wall->seed(cut[which[i]]->centre); });
    std::vector<HoleSeed> again;
    std::vector<std::size_t> again_of;
    for (std::size_t i = 0; i < which.size(); ++i)
      if (moved[i]) {
        again.push_back(*moved[i]);
        again.back().reach = seeds[which[i]].reach;
        again_of.push_back(which[i]);
      }
    const std::vector<std::optional<HoleRecord>> recut = cut_holes(mesh, again, mid_wall);
    for (std::size_t i = 0; i < again.size(); ++i)
      if (recut[i]) cut[again_of[i]] = recut[i];
  }

  std::vector<HoleRecord> found;
  std::vector<std::size_t> uncut;
  for (std::size_t i = 0; i < cut.size(); ++i) {
    if (cut[i])
      found.push_back(*cut[i]);
    else
      uncut.push_back(i);
  }
  // Two seeds in one hole (a spot the band split in two) measure it twice: the first seed keeps it.
  std::vector<char> keep(found.size(), 1);
  std::vector<Vec3> centres;
  for (const HoleRecord& r : found) centres.push_back(r.centre);
  if (centres.size() >= 2) {
    const PointTree tree(centres);
    tbb::parallel_for(std::size_t{0}, found.size(), [&](std::size_t i) {
      for (const std::size_t j : tree.k_nearest(centres[i], 4))
        if (j < i && (centres[j] - centres[i]).norm() < 0.25 * std::min(found[i].diameter, found[j].diameter))
          keep[i] = 0;
    });
  }
  HoleTable table;
  for (std::size_t i = 0; i < found.size(); ++i)
    if (keep[i]) table.holes.push_back(found[i]);
  table.dropped = seeds.size() - table.holes.size();
  table.uncut = std::move(uncut);

  centres.clear();
  for (const HoleRecord& r : table.holes) centres.push_back(r.centre);
  if (centres.size() >= 2) {
    const PointTree tree(centres);
    tbb::parallel_for(std::size_t{0}, centres.size(), [&](std::size_t i) {
      for (const std::size_t j : tree.k_nearest(centres[i], 2))
        if (j != i) table.holes[i].nearest = (centres[j] - centres[i]).norm();
    });
  }
  return table;
}

std::vector<HoleSeed> seeds_near(const MidWall& mid_wall, std::span<const Vec3> centres,
                                 std::span<const double> reach) {
  std::vector<HoleSeed> seeds(centres.size());
  tbb::parallel_for(std::size_t{0}, centres.size(), [&](std::size_t i) {
    if (std::optional<HoleSeed> s = mid_wall.seed(centres[i])) {
      seeds[i] = *s;
      seeds[i].reach = reach[i];
    }
  });
  return seeds;
}

SurfaceMidWall::SurfaceMidWall(const Surface& surface, double h, double thickness, WallOffset offset,
                               SideFunction side, double scale, const Vec3& shift)
    : surface_(surface),
      h_(h),
      shift_along_normal_(offset == WallOffset::centered  ? 0.0
                          : offset == WallOffset::outside ? 0.5 * thickness
                                                          : -0.5 * thickness),
      side_(std::move(side)),
      scale_(scale),
      shift_(shift) {}

std::optional<Vec3> SurfaceMidWall::point(const Vec3& x, const Vec3& normal) const {
  const std::optional<Vec3> cp =
      closest_point_at(surface_, (x - shift_) / scale_, h_, ClosestPointRule::exact);
  if (!cp) return std::nullopt;
  return Vec3(scale_ * (*cp + shift_along_normal_ * normal) + shift_);
}

std::optional<double> SurfaceMidWall::height(const Vec3& x, const Vec3& normal) const {
  const Vec3 y = (x - shift_) / scale_;
  const std::optional<Vec3> cp = closest_point_at(surface_, y, h_, ClosestPointRule::exact);
  if (!cp) return std::nullopt;
  const double side = side_ ? side_(y, *cp) : normal.dot(y - *cp);
  return scale_ * ((side < 0.0 ? -1.0 : 1.0) * (y - *cp).norm() - shift_along_normal_);
}

std::optional<HoleSeed> SurfaceMidWall::seed(const Vec3& x) const {
  const std::optional<Vec3> cp =
      closest_point_at(surface_, (x - shift_) / scale_, h_, ClosestPointRule::exact);
  if (!cp) return std::nullopt;
  // The tangent plane: the closest points of the 6 axis and 8 diagonal neighbours at distance h spread
  // over the surface about cp; the normal is their direction of least spread.
  std::vector<Vec3> points{*cp};
  for (int d = 0; d < 27; ++d) {
    const Vec3 step(d % 3 - 1, (d / 3) % 3 - 1, d / 9 - 1);
    const double nonzero = step.cwiseAbs().sum();
    if (nonzero == 0.0 || nonzero == 2.0) continue;  // the 6 axis and 8 corner directions
    if (auto q = closest_point_at(surface_, *cp + h_ * step.normalized(), h_, ClosestPointRule::exact))
      points.push_back(*q);
  }
  Vec3 mean = Vec3::Zero();
  for (const Vec3& p : points) mean += p;
  mean /= static_cast<double>(points.size());
  Eigen::Matrix3d spread = Eigen::Matrix3d::Zero();
  for (const Vec3& p : points) spread += (p - mean) * (p - mean).transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(spread);
  Vec3 n = eigen.eigenvectors().col(0).normalized();  // eigenvalues ascend
  if (!n.allFinite()) return std::nullopt;
  // Outward: the side function's sign, or the signed distance's rise along n (about 2 s); an unsigned
  // distance rises neither way, and a fixed choice keeps the result reproducible.
  const double s = 0.5 * h_;
  if (side_) {
    if (side_(*cp + s * n, *cp) < 0.0) n = -n;
  } else {
    const double rise = surface_.distance(*cp + s * n) - surface_.distance(*cp - s * n);
    if (rise < -s) {
      n = -n;
    } else if (!(rise > s)) {
      Eigen::Index largest = 0;
      n.cwiseAbs().maxCoeff(&largest);
      if (n[largest] < 0.0) n = -n;
    }
  }
  return HoleSeed{scale_ * (*cp + shift_along_normal_ * n) + shift_, n, 0.0};
}

}  // namespace poreshell
