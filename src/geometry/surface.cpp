#include "geometry/surface.hpp"

#include <cmath>

#include "core/error.hpp"

namespace poreshell {

Sphere::Sphere(const Vec3& center, double radius) : center_(center), radius_(radius) {
  if (!(radius > 0.0)) throw InputError("sphere radius must be positive");
}

double Sphere::distance(const Vec3& p) const {
  return (p - center_).norm() - radius_;
}

std::optional<Vec3> Sphere::closest_point(const Vec3& p) const {
  const Vec3 d = p - center_;
  const double n = d.norm();
  if (n == 0.0) return center_ + Vec3(radius_, 0, 0);  // every point is closest; pick one
  return center_ + d * (radius_ / n);
}

Box Sphere::bounds() const {
  const Vec3 r = Vec3::Constant(radius_);
  return {center_ - r, center_ + r};
}

Torus::Torus(const Vec3& center, double major_radius, double minor_radius)
    : center_(center), major_(major_radius), minor_(minor_radius) {
  if (!(minor_radius > 0.0) || !(major_radius > minor_radius))
    throw InputError("torus needs major radius > minor radius > 0");
}

double Torus::distance(const Vec3& p) const {
  const Vec3 d = p - center_;
  const double ring = std::hypot(d.x(), d.y()) - major_;
  return std::hypot(ring, d.z()) - minor_;
}

std::optional<Vec3> Torus::closest_point(const Vec3& p) const {
  const Vec3 d = p - center_;
  const double rho = std::hypot(d.x(), d.y());
  // Nearest point of the core circle; on the axis every direction is equally near.
  const Vec3 radial = rho > 0.0 ? Vec3(d.x() / rho, d.y() / rho, 0.0) : Vec3(1, 0, 0);
  const Vec3 core = radial * major_;
  const Vec3 off = d - core;
  const double n = off.norm();
  const Vec3 dir = n > 0.0 ? Vec3(off / n) : radial;
  return center_ + core + dir * minor_;
}

Box Torus::bounds() const {
  const double a = major_ + minor_;
  return {center_ - Vec3(a, a, minor_), center_ + Vec3(a, a, minor_)};
}

std::unique_ptr<Surface> make_paper_shape(const std::string& name) {
  const Vec3 c(0.5, 0.5, 0.5);
  if (name == "sphere") return std::make_unique<Sphere>(c, kPaperShapeRadius);
  if (name == "torus") return std::make_unique<Torus>(c, kPaperShapeRadius, 0.5 * kPaperShapeRadius);
  throw InputError("unknown shape '" + name + "': use sphere or torus");
}

}  // namespace poreshell
