#include "shell/edge_collapse.hpp"

// A corner table (each corner's vertex, and the corner across the edge it faces), error quadrics and
// an indexed heap of vertices. OpenMesh's DecimaterT made the same collapses under the same rules in
// 2.3-2.6 times the time, much of it in its own structures (docs/benchmarks.md "Triangle reduction on
// flat arrays").

#include <Eigen/Geometry>  // cross()
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <tuple>

namespace poreshell {
namespace {

constexpr double kMinAngleDegrees = 10.0;   // smallest angle of a new triangle
constexpr double kMaxNormalDegrees = 90.0;  // between a new triangle and the surface at its corners
constexpr std::size_t kReportEvery = 1024;  // collapses between two progress reports

// Sum of squared distances to planes, each weighted by its triangle's area: the symmetric 4 x 4
// matrix's upper triangle.
struct Quadric {
  double xx = 0, xy = 0, xz = 0, xw = 0, yy = 0, yz = 0, yw = 0, zz = 0, zw = 0, ww = 0;

  static Quadric plane(const Vec3& n, double d, double weight) {
    return {weight * n.x() * n.x(), weight * n.x() * n.y(), weight * n.x() * n.z(), weight * n.x() * d,
            weight * n.y() * n.y(), weight * n.y() * n.z(), weight * n.y() * d,     weight * n.z() * n.z(),
            weight * n.z() * d,     weight * d * d};
  }
  Quadric& operator+=(const Quadric& o) {
    xx += o.xx, xy += o.xy, xz += o.xz, xw += o.xw, yy += o.yy;
    yz += o.yz, yw += o.yw, zz += o.zz, zw += o.zw, ww += o.ww;
    return *this;
  }
  // The sum of squared distances at p.
  double at(const Vec3& p) const {
    const double x = p.x(), y = p.y(), z = p.z();
    return x * (xx * x + 2.0 * (xy * y + xz * z + xw)) + y * (yy * y + 2.0 * (yz * z + yw)) +
           z * (zz * z + 2.0 * zw) + ww;
  }
};

// A min-heap of vertices keyed by (key, vertex), each vertex's place kept so that its key can change.
class VertexHeap {
 public:
  explicit VertexHeap(std::size_t vertices) : place_(vertices, -1), key_(vertices, 0.0) {}

  bool empty() const { return heap_.empty(); }
  std::int32_t top() const { return heap_.front(); }

  void set(std::int32_t v, double key) {
    const auto u = static_cast<std::size_t>(v);
    if (place_[u] < 0) {
      key_[u] = key;
      place_[u] = static_cast<std::int32_t>(heap_.size());
      heap_.push_back(v);
      up(heap_.size() - 1);
      return;
    }
    const bool lower = key < key_[u];
    key_[u] = key;
    if (lower)
      up(static_cast<std::size_t>(place_[u]));
    else
      down(static_cast<std::size_t>(place_[u]));
  }
  void remove(std::int32_t v) {
    const auto u = static_cast<std::size_t>(v);
    if (place_[u] < 0) return;
    const auto i = static_cast<std::size_t>(place_[u]);
    place_[u] = -1;
    const std::int32_t last = heap_.back();
    heap_.pop_back();
    if (i == heap_.size()) return;
    heap_[i] = last;
    place_[static_cast<std::size_t>(last)] = static_cast<std::int32_t>(i);
    up(i);
    down(static_cast<std::size_t>(place_[static_cast<std::size_t>(last)]));
  }

 private:
  bool less(std::int32_t a, std::int32_t b) const {
    const double ka = key_[static_cast<std::size_t>(a)], kb = key_[static_cast<std::size_t>(b)];
    return ka < kb || (ka == kb && a < b);
  }
  void put(std::size_t i, std::int32_t v) {
    heap_[i] = v;
    place_[static_cast<std::size_t>(v)] = static_cast<std::int32_t>(i);
  }
  void up(std::size_t i) {
    const std::int32_t v = heap_[i];
    while (i > 0 && less(v, heap_[(i - 1) / 2])) {
      put(i, heap_[(i - 1) / 2]);
      i = (i - 1) / 2;
    }
    put(i, v);
  }
  void down(std::size_t i) {
    const std::int32_t v = heap_[i];
    for (;;) {
      std::size_t child = 2 * i + 1;
      if (child >= heap_.size()) break;
      if (child + 1 < heap_.size() && less(heap_[child + 1], heap_[child])) ++child;
      if (!less(heap_[child], v)) break;
      put(i, heap_[child]);
      i = child;
    }
    put(i, v);
  }

  std::vector<std::int32_t> heap_, place_;
  std::vector<double> key_;
};

// A collapse is named by the corner c of v0 in the triangle that runs v0 -> v1 -> vl; the triangle
// across the edge runs v1 -> v0 -> vr.
class Collapser {
 public:
  Collapser(const TriangleMesh& mesh, const std::vector<std::int32_t>& opposite,
            const OriginalSurface& original, double tolerance)
      : points_(mesh.vertices),
        original_(original),
        tolerance_(tolerance),
        corners_(3 * mesh.triangles.size()),
        vertex_corner_(mesh.vertices.size(), -1),
        valence_(mesh.vertices.size(), 0),
        dead_(mesh.triangles.size(), 0),
        live_(mesh.triangles.size()),
        quadric_(mesh.vertices.size()),
        sine_(mesh.triangles.size()),
        first_point_(mesh.triangles.size(), -1),
        next_point_(mesh.vertices.size(), -1),
        mark_(mesh.vertices.size(), 0),
        bound_(mesh.vertices.size(), 0.0),
        checked_(mesh.vertices.size(), 0),
        target_(mesh.vertices.size(), -1),
        heap_(mesh.vertices.size()),
        cache_(mesh.triangles.size()) {
    // A closed manifold's vertex has as many triangles as edges: its valence counts its corners.
    for (std::size_t f = 0; f < mesh.triangles.size(); ++f) {
      const auto& t = mesh.triangles[f];
      for (int k = 0; k < 3; ++k) {
        corners_[3 * f + k] = {t[k], opposite[3 * f + k]};
        vertex_corner_[static_cast<std::size_t>(t[k])] = static_cast<std::int32_t>(3 * f + k);
        ++valence_[static_cast<std::size_t>(t[k])];
      }
      const Vec3 &a = points_[t[0]], &b = points_[t[1]], &c = points_[t[2]];
      const Vec3 n = (b - a).cross(c - a);
      const double twice_area = n.norm();
      const Vec3 unit = twice_area > 0.0 ? Vec3(n / twice_area) : Vec3::Zero();
      const Quadric q = Quadric::plane(unit, -unit.dot(a), 0.5 * twice_area);
      for (int k = 0; k < 3; ++k) quadric_[static_cast<std::size_t>(t[k])] += q;
      sine_[f] = min_angle_sine(a, b, c);
    }
    for (std::size_t v = 0; v < points_.size(); ++v)
      if (vertex_corner_[v] >= 0) rate(static_cast<std::int32_t>(v));
  }

  void run(std::size_t target, const StageProgress& progress) {
    const std::size_t collapses = live_ > target ? (live_ - target) / 2 : 0;
    std::size_t done = 0;
    while (live_ > target && !heap_.empty()) {
      const std::int32_t v = heap_.top();
      const auto u = static_cast<std::size_t>(v);
      if (!checked_[u] || vertex(target_[u]) != v || !topology_ok(target_[u])) {
        choose(v);
        continue;
      }
      const std::int32_t kept = vertex(next_corner(target_[u]));
      collapse(target_[u]);
      // Every vertex whose collapses the change could touch is next to the kept one. Its collapses'
      // errors only grow (the kept vertex's quadric did), but for its collapse onto the kept vertex,
      // new where it was next to v0: that one lowers its bound, if any.
      rate(kept);
      for (const std::int32_t c : fan_kept_) {  // collapse() left the kept vertex's fan there
        const std::int32_t w = vertex(next_corner(c));
        const auto x = static_cast<std::size_t>(w);
        bound_[x] = std::min(bound_[x], error(w, kept));
        checked_[x] = 0;
        heap_.set(w, bound_[x]);
      }
      if (++done % kReportEvery == 0)
        progress.advance(static_cast<double>(done) / static_cast<double>(collapses));
    }
    progress.check();
  }

  std::vector<std::array<std::int32_t, 3>> triangles() const {
    std::vector<std::array<std::int32_t, 3>> out;
    out.reserve(live_);
    for (std::size_t f = 0; f < dead_.size(); ++f)
      if (!dead_[f])
        out.push_back({corners_[3 * f].vertex, corners_[3 * f + 1].vertex, corners_[3 * f + 2].vertex});
    return out;
  }

 private:
  struct NewTriangle {
    std::array<std::int32_t, 3> v;
    int kept;  // the corner where v0 was
  };

  std::int32_t vertex(std::int32_t c) const { return corners_[static_cast<std::size_t>(c)].vertex; }
  std::int32_t across(std::int32_t c) const { return corners_[static_cast<std::size_t>(c)].opposite; }
  const Vec3& point(std::int32_t v) const { return points_[static_cast<std::size_t>(v)]; }

  // The corners of v, turning around it.
  void fan(std::int32_t v, std::vector<std::int32_t>& out) const {
    out.clear();
    const std::int32_t first = vertex_corner_[static_cast<std::size_t>(v)];
    std::int32_t c = first;
    do {
      out.push_back(c);
      c = next_corner(across(next_corner(c)));
    } while (c != first);
  }
  // The link condition: v0 and v1 share no neighbour but vl and vr. A valence-3 vertex beside the
  // edge would be left with two triangles back to back.
  bool topology_ok(std::int32_t c) {
    if (c < 0 || dead_[static_cast<std::size_t>(c / 3)]) return false;
    mark_neighbours(vertex(c));
    return link_ok(c);
  }

  // Of the collapse of v0 onto v1. Round-off can make the quadric of a flat collapse negative.
  double error(std::int32_t v0, std::int32_t v1) const {
    const Vec3& p1 = point(v1);
    return std::max(
        quadric_[static_cast<std::size_t>(v0)].at(p1) + quadric_[static_cast<std::size_t>(v1)].at(p1), 0.0);
  }
  double error(std::int32_t c) const { return error(vertex(c), vertex(next_corner(c))); }

  // Whether the collapse through corner c of v keeps the mesh 2-manifold, with v's neighbours
  // marked (mark_neighbours(v)): the test of topology_ok().
  bool link_ok(std::int32_t c) {
    const std::int32_t v1 = vertex(next_corner(c)), vl = vertex(previous_corner(c));
    const std::int32_t vr = vertex(across(previous_corner(c)));
    if (vl == vr || valence_[static_cast<std::size_t>(vl)] <= 3 ||
        valence_[static_cast<std::size_t>(vr)] <= 3)
      return false;
    fan(v1, scratch_);
    for (const std::int32_t k : scratch_) {
      const std::int32_t w = vertex(next_corner(k));
      if (w != vl && w != vr && mark_[static_cast<std::size_t>(w)] == stamp_) return false;
    }
    return true;
  }
  void mark_neighbours(std::int32_t v) {
    fan(v, fan_rated_);
    ++stamp_;
    for (const std::int32_t c : fan_rated_) mark_[static_cast<std::size_t>(vertex(next_corner(c)))] = stamp_;
  }

  // The least error of v's collapses: a lower bound on the collapse choose() would make, which is
  // all the heap needs until v comes to its top (so the link condition, which costs a walk around
  // each neighbour, waits until then too).
  void rate(std::int32_t v) {
    const auto u = static_cast<std::size_t>(v);
    checked_[u] = 0;
    fan(v, fan_rated_);
    bound_[u] = std::numeric_limits<double>::infinity();
    for (const std::int32_t c : fan_rated_) bound_[u] = std::min(bound_[u], error(c));
    heap_.set(v, bound_[u]);
  }

  // v's least-error collapse that passes all the rules, or none: v leaves the heap until a collapse
  // next to it rates it again.
  void choose(std::int32_t v) {
    const auto u = static_cast<std::size_t>(v);
    mark_neighbours(v);
    candidates_.clear();
    for (const std::int32_t c : fan_rated_) candidates_.emplace_back(error(c), vertex(next_corner(c)), c);
    std::sort(candidates_.begin(), candidates_.end());  // ties by the kept vertex: deterministic
    bound_[u] = std::get<0>(candidates_.front());
    for (const auto& [e, kept, c] : candidates_)
      if (link_ok(c) && shape_ok(c) && near_ok() && hausdorff_ok(c)) {
        checked_[u] = 1;
        target_[u] = c;
        heap_.set(v, e);
        return;
      }
    checked_[u] = 0;
    heap_.remove(v);
  }

  // Angles and normals of the triangles the collapse changes; keeps them in ring_ for the checks
  // after.
  bool shape_ok(std::int32_t c) {
    const std::int32_t v0 = vertex(c), v1 = vertex(next_corner(c));
    const std::int32_t left = c / 3, right = across(previous_corner(c)) / 3;
    fan(v0, fan_check_);
    double before = 1.0;
    for (const std::int32_t k : fan_check_) before = std::min(before, sine_[static_cast<std::size_t>(k / 3)]);
    const double least = std::min(min_sine_, before);
    ring_.clear();
    for (const std::int32_t k : fan_check_) {
      if (k / 3 == left || k / 3 == right) continue;  // removed by the collapse
      NewTriangle t{{vertex(k), vertex(next_corner(k)), vertex(previous_corner(k))}, 0};
      t.v[0] = v1;
      const Vec3 &a = point(t.v[0]), &b = point(t.v[1]), &d = point(t.v[2]);
      if (min_angle_sine(a, b, d) < least) return false;
      const Vec3 n = (b - a).cross(d - a).stableNormalized();
      for (const std::int32_t w : t.v)
        if (original_.normal(w).dot(n) < min_cos_) return false;
      ring_.push_back(t);
    }
    return true;
  }

  // Each new edge is the edge from v1 onwards of one new triangle.
  bool near_ok() {
    for (const NewTriangle& t : ring_) {
      const std::int32_t a = t.v[0], b = t.v[1], d = t.v[2];  // not a structured binding: lambdas use them
      const Vec3 centroid = (point(a) + point(b) + point(d)) / 3.0;
      if (!cache_.get(a, b, d, [&] { return original_.near(centroid, {a, b, d}, tolerance_); })) return false;
      const Vec3 midpoint = 0.5 * (point(a) + point(b));
      if (!cache_.get(a, b, -1, [&] { return original_.near(midpoint, {a, b}, tolerance_); })) return false;
    }
    return true;
  }

  // The vertex removed and the original vertices removed before, on the triangles around it, each
  // within the tolerance of one of the new triangles.
  bool hausdorff_ok(std::int32_t c) {
    const double tolerance2 = tolerance_ * tolerance_;
    const auto within = [&](const Vec3& p) {
      for (const NewTriangle& t : ring_)
        if ((closest_point_on_triangle(p, point(t.v[0]), point(t.v[1]), point(t.v[2])) - p).squaredNorm() <=
            tolerance2)
          return true;
      return false;
    };
    if (!within(point(vertex(c)))) return false;
    for (const std::int32_t k : fan_check_)
      for (std::int32_t p = first_point_[static_cast<std::size_t>(k / 3)]; p >= 0;
           p = next_point_[static_cast<std::size_t>(p)])
        if (!within(point(p))) return false;
    return true;
  }

  std::int32_t corner_in(std::int32_t triangle, std::int32_t v) const {
    for (std::int32_t k = 3 * triangle; k < 3 * triangle + 3; ++k)
      if (vertex(k) == v) return k;
    throw std::runtime_error("mesh decimation: a corner table lost a vertex");
  }

  void collapse(std::int32_t c) {
    const std::int32_t v0 = vertex(c), v1 = vertex(next_corner(c)), vl = vertex(previous_corner(c));
    const std::int32_t e = across(previous_corner(c));  // vr's corner
    const std::int32_t vr = vertex(e), left = c / 3, right = e / 3;
    const std::int32_t right0 = previous_corner(e), right1 = next_corner(e);  // v0's and v1's
    fan(v0, fan_check_);
    // The triangles across the removed ones' outer edges now face each other.
    const std::int32_t a = across(c), b = across(next_corner(c)), f = across(right0), g = across(right1);
    corners_[static_cast<std::size_t>(a)].opposite = b;
    corners_[static_cast<std::size_t>(b)].opposite = a;
    corners_[static_cast<std::size_t>(f)].opposite = g;
    corners_[static_cast<std::size_t>(g)].opposite = f;
    for (const std::int32_t k : fan_check_)
      if (k / 3 != left && k / 3 != right) corners_[static_cast<std::size_t>(k)].vertex = v1;
    dead_[static_cast<std::size_t>(left)] = dead_[static_cast<std::size_t>(right)] = 1;
    live_ -= 2;
    vertex_corner_[static_cast<std::size_t>(v0)] = -1;
    vertex_corner_[static_cast<std::size_t>(v1)] = corner_in(a / 3, v1);
    vertex_corner_[static_cast<std::size_t>(vl)] = corner_in(a / 3, vl);
    vertex_corner_[static_cast<std::size_t>(vr)] = corner_in(f / 3, vr);
    heap_.remove(v0);
    // v1 gains v0's neighbours but the shared vl and vr (the link condition); they lose v0.
    valence_[static_cast<std::size_t>(v1)] += valence_[static_cast<std::size_t>(v0)] - 4;
    --valence_[static_cast<std::size_t>(vl)];
    --valence_[static_cast<std::size_t>(vr)];
    quadric_[static_cast<std::size_t>(v1)] += quadric_[static_cast<std::size_t>(v0)];

    fan(v1, fan_kept_);
    for (const std::int32_t k : fan_kept_) {
      const std::int32_t t = k / 3;
      sine_[static_cast<std::size_t>(t)] =
          min_angle_sine(point(vertex(3 * t)), point(vertex(3 * t + 1)), point(vertex(3 * t + 2)));
    }
    // The removed vertices on the changed triangles, and v0, each go to the nearest triangle around v1.
    moved_.clear();
    const auto take = [&](std::int32_t t) {
      for (std::int32_t p = first_point_[static_cast<std::size_t>(t)]; p >= 0;
           p = next_point_[static_cast<std::size_t>(p)])
        moved_.push_back(p);
      first_point_[static_cast<std::size_t>(t)] = -1;
    };
    take(left);
    take(right);
    for (const std::int32_t k : fan_kept_) take(k / 3);
    moved_.push_back(v0);
    for (const std::int32_t p : moved_) {
      double best = std::numeric_limits<double>::infinity();
      std::int32_t nearest = fan_kept_.front() / 3;
      for (const std::int32_t k : fan_kept_) {
        const std::int32_t t = k / 3;
        const Vec3 q = closest_point_on_triangle(point(p), point(vertex(3 * t)), point(vertex(3 * t + 1)),
                                                 point(vertex(3 * t + 2)));
        if (const double d2 = (q - point(p)).squaredNorm(); d2 < best) {
          best = d2;
          nearest = t;
        }
      }
      next_point_[static_cast<std::size_t>(p)] = first_point_[static_cast<std::size_t>(nearest)];
      first_point_[static_cast<std::size_t>(nearest)] = p;
    }
  }

  const std::vector<Vec3>& points_;
  const OriginalSurface& original_;
  const double tolerance_;
  const double min_sine_ = std::sin(kMinAngleDegrees * std::numbers::pi / 180.0);
  const double min_cos_ = std::cos(kMaxNormalDegrees * std::numbers::pi / 180.0);

  // Each corner's vertex and the corner across the edge it faces, side by side: walking around a
  // vertex reads both, and on a mesh of a million triangles that walk is mostly cache misses.
  struct Corner {
    std::int32_t vertex, opposite;
  };
  std::vector<Corner> corners_;
  std::vector<std::int32_t> vertex_corner_;  // a corner of each vertex in a live triangle; -1: removed
  std::vector<std::int32_t> valence_;        // per vertex
  std::vector<char> dead_;                   // per triangle
  std::size_t live_;
  std::vector<Quadric> quadric_;  // per vertex
  std::vector<double> sine_;      // of each triangle's smallest angle, kept up to date
  // The removed vertices, each on the list of the triangle it is nearest among those it was
  // distributed over: first_point_ per triangle, next_point_ per vertex, -1 ends a list.
  std::vector<std::int32_t> first_point_, next_point_;

  std::vector<std::uint32_t> mark_;  // stamp_ on v1's neighbours during a link test
  std::uint32_t stamp_ = 0;
  std::vector<double> bound_;         // per vertex: at most the error of each of its collapses
  std::vector<char> checked_;         // target_ passed all the rules and the heap holds its error
  std::vector<std::int32_t> target_;  // per vertex: the collapse chosen
  VertexHeap heap_;
  NearCache cache_;

  // Scratch, kept to save allocations.
  std::vector<std::int32_t> scratch_, fan_rated_, fan_check_, fan_kept_, moved_;
  std::vector<std::tuple<double, std::int32_t, std::int32_t>> candidates_;  // (error, v1, corner)
  std::vector<NewTriangle> ring_;
};

}  // namespace

std::vector<std::array<std::int32_t, 3>> collapse_edges(const TriangleMesh& mesh,
                                                        const std::vector<std::int32_t>& opposite,
                                                        const OriginalSurface& original,
                                                        std::int64_t max_triangles, double tolerance,
                                                        const StageProgress& progress) {
  Collapser collapser(mesh, opposite, original, tolerance);
  collapser.run(static_cast<std::size_t>(max_triangles), progress);
  return collapser.triangles();
}

}  // namespace poreshell
