#include "geometry/winding_number.hpp"

#include <Eigen/Geometry>  // cross()
#include <algorithm>
#include <cmath>
#include <numbers>

#include "core/error.hpp"

namespace poreshell {
namespace {

constexpr std::int32_t kLeafSize = 8;

// Signed solid angle of triangle (a, b, c) seen from the origin (Van Oosterom and Strackee 1983);
// positive when the origin lies behind the triangle (on the side its normal points away from).
double solid_angle(const Vec3& a, const Vec3& b, const Vec3& c) {
  const double la = a.norm(), lb = b.norm(), lc = c.norm();
  const double det = a.dot(b.cross(c));
  const double denominator = la * lb * lc + a.dot(b) * lc + b.dot(c) * la + c.dot(a) * lb;
  return 2.0 * std::atan2(det, denominator);
}

}  // namespace

WindingNumber::WindingNumber(const TriangleMesh& mesh, double accuracy) : beta_(accuracy) {
  std::vector<Tri> tris;
  tris.reserve(mesh.triangles.size());
  for (const auto& t : mesh.triangles)
    tris.push_back({mesh.vertices.at(t[0]), mesh.vertices.at(t[1]), mesh.vertices.at(t[2])});
  if (tris.empty()) throw InputError("the winding number needs a mesh with at least one triangle");
  if (tris.size() > static_cast<std::size_t>(INT32_MAX / 2))
    throw InputError("the mesh has too many triangles for the winding number's index");
  std::vector<std::int32_t> order(tris.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = static_cast<std::int32_t>(i);
  nodes_.reserve(2 * tris.size() / kLeafSize + 2);
  nodes_.emplace_back();
  build(0, order, tris, 0, static_cast<std::int32_t>(tris.size()));
  tris_.reserve(tris.size());
  for (std::int32_t i : order) tris_.push_back(tris[i]);
}

void WindingNumber::build(std::int32_t node, std::vector<std::int32_t>& order, const std::vector<Tri>& tris,
                          std::int32_t begin, std::int32_t end) {
  Vec3 lo = Vec3::Constant(INFINITY), hi = Vec3::Constant(-INFINITY);
  Vec3 weighted = Vec3::Zero(), dipole = Vec3::Zero();
  double area = 0.0;
  for (std::int32_t i = begin; i < end; ++i) {
    const Tri& t = tris[order[i]];
    const Vec3 centroid = (t.a + t.b + t.c) / 3.0;
    lo = lo.cwiseMin(centroid);
    hi = hi.cwiseMax(centroid);
    const Vec3 n = 0.5 * (t.b - t.a).cross(t.c - t.a);
    dipole += n;
    weighted += n.norm() * centroid;
    area += n.norm();
  }
  const Vec3 center = area > 0.0 ? Vec3(weighted / area) : Vec3(0.5 * (lo + hi));
  double radius = 0.0;
  Eigen::Matrix3d moment = Eigen::Matrix3d::Zero();
  for (std::int32_t i = begin; i < end; ++i) {
    const Tri& t = tris[order[i]];
    radius = std::max({radius, (t.a - center).norm(), (t.b - center).norm(), (t.c - center).norm()});
    moment += 0.5 * (t.b - t.a).cross(t.c - t.a) * ((t.a + t.b + t.c) / 3.0 - center).transpose();
  }
  nodes_[node].center = center;
  nodes_[node].dipole = dipole;
  nodes_[node].moment = moment;
  nodes_[node].radius = radius;
  if (end - begin <= kLeafSize) {
    nodes_[node].first = begin;
    nodes_[node].count = end - begin;
    return;
  }
  // Median split of the centroids along the longest axis of their box.
  int axis = 0;
  (hi - lo).maxCoeff(&axis);
  const std::int32_t mid = begin + (end - begin) / 2;
  std::nth_element(order.begin() + begin, order.begin() + mid, order.begin() + end,
                   [&](std::int32_t x, std::int32_t y) {
                     const double cx = tris[x].a[axis] + tris[x].b[axis] + tris[x].c[axis];
                     const double cy = tris[y].a[axis] + tris[y].b[axis] + tris[y].c[axis];
                     return cx != cy ? cx < cy : x < y;
                   });
  const auto left = static_cast<std::int32_t>(nodes_.size());
  nodes_.emplace_back();
  nodes_.emplace_back();
  nodes_[node].first = left;
  nodes_[node].count = 0;
  build(left, order, tris, begin, mid);
  build(left + 1, order, tris, mid, end);
}

double WindingNumber::operator()(const Vec3& q) const {
  double total = 0.0;
  std::int32_t stack[64];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& node = nodes_[stack[--top]];
    const Vec3 r = node.center - q;
    const double distance = r.norm();
    if (distance > beta_ * node.radius) {
      // Far cluster: sum of a_i n_i . K(c_i - q), K(r) = r / |r|^3, expanded around r = center - q to
      // first order in c_i - center: N . K(r) + J(r) : M with J = I / |r|^3 - 3 r r^T / |r|^5.
      const double inv3 = 1.0 / (distance * distance * distance);
      total += inv3 * (r.dot(node.dipole) + node.moment.trace() -
                       3.0 * r.dot(node.moment * r) / (distance * distance));
    } else if (node.count > 0) {
      for (std::int32_t i = node.first; i < node.first + node.count; ++i) {
        const Tri& t = tris_[i];
        total += solid_angle(t.a - q, t.b - q, t.c - q);
      }
    } else {
      stack[top++] = node.first;
      stack[top++] = node.first + 1;
    }
  }
  return total / (4.0 * std::numbers::pi);
}

double WindingNumber::exact(const Vec3& q) const {
  double total = 0.0;
  for (const Tri& t : tris_) total += solid_angle(t.a - q, t.b - q, t.c - q);
  return total / (4.0 * std::numbers::pi);
}

double side_of_surface(const WindingNumber& winding, const Vec3& x, const Vec3& closest, double step) {
  const Vec3 v = x - closest;
  const double length = v.norm();
  if (!(length > 0.0)) return 0.0;  // on the surface: either side
  const Vec3 probe = v * (std::min(step, length) / length);
  const double behind = winding(closest - probe), ahead = winding(closest + probe);
  if (std::abs(behind - ahead) >= 0.5) return behind - ahead;
  // No clear jump: c lies on an open boundary (a scan's hole, a sheet's edge). Compare w(x) with w
  // at c (the mean of the two probes): about 1/2 on a closed-ish model, so a point inside a scan's
  // hole counts as inside; about 0 at a sheet's edge, so its normal still decides.
  return 0.5 * (behind + ahead) - winding(x);
}

}  // namespace poreshell
