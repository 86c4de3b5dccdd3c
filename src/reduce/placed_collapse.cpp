#include "reduce/placed_collapse.hpp"

// Edge collapses that place the vertex they keep, on flat arrays: the corner table and the parts of
// edge_collapse.cpp, with three differences. The kept vertex goes where the two vertices' quadrics
// are least (Garland and Heckbert), pulled a little towards the edge's midpoint where the quadric is
// flat (a cylinder's axis, a plane); so a chord across a curved surface lies half above and half
// below it, where one between two of its vertices lies all on one side. Each collapse is measured
// against the original surface directly, both ways: every original vertex (the removed and the moved
// ones) and every original triangle's centroid carried by the triangles around the edge is within the
// tolerance of one of the new triangles, and the new vertex, the new triangles' centroids and quarter
// centroids and the new edges' midpoints are within it of the original surface; no bound is carried
// from one collapse to the next, so none grows. And a vertex's collapses are checked again each time
// it comes to the top of the queue, since moving a vertex changes the triangles around every
// neighbour. Measured in docs/benchmarks.md "Placed collapses".

#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <tuple>

#include "reduce/collapse_queue.hpp"
#include "reduce/corner_table.hpp"

namespace poreshell {
namespace {

constexpr double kMinAngleDegrees = 10.0;   // smallest angle of a new triangle
constexpr double kMaxNormalDegrees = 90.0;  // between a new triangle and the surface at its corners
constexpr std::size_t kReportEvery = 1024;  // collapses between two progress reports
// The pull towards the midpoint, as a fraction of the quadric's mean curvature of the error: enough to
// hold the vertex where the quadric does not (along a plane or a cylinder's axis), too little to move
// it where it does.
constexpr double kPull = 1e-3;

// The point where q is least, pulled towards `midpoint` by kPull: (A + d I) p = d m - b.
Vec3 place(const Quadric& q, const Vec3& midpoint) {
  const double d = kPull * (q.xx + q.yy + q.zz) / 3.0;
  Eigen::Matrix3d a;
  a << q.xx + d, q.xy, q.xz, q.xy, q.yy + d, q.yz, q.xz, q.yz, q.zz + d;
  const Vec3 rhs = d * midpoint - Vec3(q.xw, q.yw, q.zw);
  const double det = a.determinant();
  if (!(std::abs(det) > 1e-300)) return midpoint;
  const Vec3 p = a.inverse() * rhs;
  return p.allFinite() ? p : midpoint;
}

// A triangle as the distance tests need it: a point within the tolerance of its plane whose foot lies
// inside it is within the tolerance of it, with no search for the nearest point (which a point under
// a neighbour would need: those few go to closest_point_on_triangle()).
struct Flat {
  Vec3 a, e0, e1, normal;
  double d00, d01, d11, det;

  static Flat of(const Vec3& a, const Vec3& b, const Vec3& c) {
    return of(a, b, c, (b - a).cross(c - a).stableNormalized());
  }
  // With the unit normal known (the original triangles'): no square root, no division.
  static Flat of(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& normal) {
    Flat f{a, b - a, c - a, normal, 0, 0, 0, 0};
    f.d00 = f.e0.squaredNorm(), f.d01 = f.e0.dot(f.e1), f.d11 = f.e1.squaredNorm();
    f.det = f.d00 * f.d11 - f.d01 * f.d01;
    return f;
  }
  // 1: within `tolerance` over the triangle; 0: not; -1: within of its plane, its foot outside it.
  // The foot's barycentric coordinates times det, so that no division is needed.
  int over(const Vec3& x, double tolerance) const {
    if (!(std::abs(normal.dot(x - a)) <= tolerance)) return 0;
    return foot_inside(x) ? 1 : -1;
  }
  // Whether x's foot on the plane lies inside the triangle.
  bool foot_inside(const Vec3& x) const {
    const Vec3 d = x - a;
    const double d20 = d.dot(e0), d21 = d.dot(e1);
    const double u = d11 * d20 - d01 * d21, v = d00 * d21 - d01 * d20;
    return det > 0.0 && u >= 0.0 && v >= 0.0 && u + v <= det;
  }
};

class PlacedCollapser : CornerTable {
 public:
  PlacedCollapser(const TriangleMesh& mesh, const std::vector<std::int32_t>& opposite,
                  const OriginalSurface& original, double tolerance)
      : original_(original), tolerance_(tolerance) {
    original_triangles_ = &mesh.triangles;
    const std::size_t nv = mesh.vertices.size(), nf = mesh.triangles.size();
    tbb::parallel_invoke(
        [&] {
          points_ = mesh.vertices;
          // The original's vertices, then its triangles' centroids: the points the new triangles must
          // stay near. Each centroid starts on its own triangle.
          samples_ = mesh.vertices;
          samples_.resize(nv + nf);
          first_point_.resize(nf);
          next_point_.assign(nv + nf, -1);
          for (std::size_t f = 0; f < nf; ++f) {
            const auto& t = mesh.triangles[f];
            samples_[nv + f] = (mesh.vertices[t[0]] + mesh.vertices[t[1]] + mesh.vertices[t[2]]) / 3.0;
            first_point_[f] = static_cast<std::int32_t>(nv + f);
          }
          carried_.assign(nv, 0);
          owner_.assign(nv, 0);
          target_.assign(nv, -1);
          target_point_.resize(nv);
        },
        [&] { quadric_ = vertex_quadrics(mesh); },
        [&] {
          build_table(mesh, opposite);
          sine_.resize(nf);
          tbb::parallel_for(std::size_t{0}, nf, [&](std::size_t f) {
            const auto& t = mesh.triangles[f];
            sine_[f] = min_angle_sine_squared(mesh.vertices[t[0]], mesh.vertices[t[1]], mesh.vertices[t[2]]);
          });
        });
    original_normal_.resize(nf);
    original_shape_.resize(nf);
    tbb::parallel_for(std::size_t{0}, nf, [&](std::size_t f) {
      const auto& t = mesh.triangles[f];
      original_shape_[f] = classify_triangle(mesh.vertices[t[0]], mesh.vertices[t[1]], mesh.vertices[t[2]]);
      original_normal_[f] = (mesh.vertices[t[1]] - mesh.vertices[t[0]])
                                .cross(mesh.vertices[t[2]] - mesh.vertices[t[0]])
                                .stableNormalized();
    });
  }

  void run(std::size_t target, CollapseCounts& counts, const StageProgress& progress) {
    run_in_parts(
        points_, target, 1, counts, progress,
        [&](int part, std::size_t) { return Worker(part, points_.size()); },
        [&](Worker& w, std::size_t quota, const std::vector<char>& candidate, LoopProgress& loop) {
          return collapse_until(w, quota, candidate, loop);
        });
  }

  CollapsedMesh result() const {
    CollapsedMesh out = live_mesh(first_point_, next_point_, points_.size());
    out.positions = points_;
    return out;
  }

 private:
  // A triangle of the new fan: the new vertex, then b and d; `old` the triangle it replaces.
  struct RingTriangle {
    std::int32_t b, d, old;
    TriangleShape shape;
  };

  struct Worker {
    Worker(int owned_part, std::size_t vertices) : part(owned_part), queue(vertices), mark(vertices, 0) {}
    int part;
    VertexQueue<> queue;
    std::vector<std::uint32_t> mark;
    std::uint32_t stamp = 0;
    std::vector<std::int32_t> scratch, fan0, fan1, fan_new, moved;
    std::vector<std::tuple<double, std::int32_t, std::int32_t>> candidates;  // (error, v1, corner)
    std::vector<Vec3> placed;                                                // per candidate
    std::vector<RingTriangle> ring;
    std::vector<Flat> ring_flat;
    // Original triangles under the old fan (their centroids are carried), by the ring triangle their
    // centroid is near: those of ring triangle r from bucket[r] to bucket[r + 1].
    std::vector<std::pair<std::int32_t, std::int32_t>> under;  // (ring triangle, original triangle)
    std::vector<std::int32_t> nearby;
    std::vector<std::size_t> bucket;
    CollapseCounts counts;
  };

  // Collapses until `quota` triangles are gone or none of the worker's vertices can move. A vertex at
  // the top is checked (choose()) unless it was just checked: its key is then its collapse's error.
  std::size_t collapse_until(Worker& w, std::size_t quota, const std::vector<char>& candidate,
                             LoopProgress& loop) {
    for (std::size_t v = 0; v < points_.size(); ++v)
      if (candidate[v] && vertex_corner_[v] >= 0 && owns(w, static_cast<std::int32_t>(v)))
        rate(w, static_cast<std::int32_t>(v));
    std::size_t removed = 0, unreported = 0;
    std::int32_t just_chosen = -1;
    while (removed < quota && !w.queue.empty()) {
      const std::int32_t v = w.queue.top();
      if (v != just_chosen) {
        choose(w, v);
        just_chosen = v;
        continue;
      }
      just_chosen = -1;
      const auto u = static_cast<std::size_t>(v);
      ++w.counts.checked;
      const std::int32_t kept = vertex(next_corner(target_[u]));
      collapse(w, target_[u], target_point_[u]);
      removed += 2;
      rate(w, kept);
      for (const std::int32_t c : w.fan_new) {
        const std::int32_t n = vertex(next_corner(c));
        if (owns(w, n)) rate(w, n);
      }
      if (++unreported == kReportEvery) {
        loop.done(unreported);
        unreported = 0;
      }
    }
    loop.done(unreported);
    return removed;
  }

  bool owns(const Worker& w, std::int32_t v) const { return owner_[static_cast<std::size_t>(v)] == w.part; }
  const Vec3& point(std::int32_t v) const { return points_[static_cast<std::size_t>(v)]; }

  // Where the collapse through corner c (v0 -> v1) puts the kept vertex, and its error.
  std::pair<Vec3, double> placement(std::int32_t c) const {
    const std::int32_t v0 = vertex(c), v1 = vertex(next_corner(c));
    Quadric q = quadric_[static_cast<std::size_t>(v0)];
    q += quadric_[static_cast<std::size_t>(v1)];
    const Vec3 p = place(q, 0.5 * (point(v0) + point(v1)));
    return {p, std::max(q.at(p), 0.0)};
  }

  // A lower bound of v's collapses' errors, for the queue until v comes to its top.
  void rate(Worker& w, std::int32_t v) {
    fan(v, w.scratch);
    double least = std::numeric_limits<double>::infinity();
    for (const std::int32_t c : w.scratch) least = std::min(least, placement(c).second);
    w.queue.set(v, least);
  }

  // v's least-error collapse that passes every rule, its key then its error; or none, and v leaves the
  // queue until a collapse next to it rates it again.
  void choose(Worker& w, std::int32_t v) {
    const auto u = static_cast<std::size_t>(v);
    fan(v, w.fan0);
    ++w.stamp;
    for (const std::int32_t c : w.fan0) w.mark[static_cast<std::size_t>(vertex(next_corner(c)))] = w.stamp;
    w.candidates.clear();
    w.placed.clear();
    for (const std::int32_t c : w.fan0) {
      const std::int32_t n = vertex(next_corner(c));
      if (!owns(w, n)) continue;
      const auto [p, e] = placement(c);
      w.candidates.emplace_back(e, n, static_cast<std::int32_t>(w.placed.size()));
      w.placed.push_back(p);
    }
    std::sort(w.candidates.begin(), w.candidates.end());
    double before = 1.0;
    for (const std::int32_t k : w.fan0) before = std::min(before, sine_[static_cast<std::size_t>(k / 3)]);
    for (const auto& [e, kept, index] : w.candidates) {
      const std::int32_t c = corner_towards(w.fan0, kept);
      if (!link_ok(c, w.mark, w.stamp, w.scratch)) continue;
      fan(kept, w.fan1);
      // The quadric's point first; where its triangles are too sharp, or too far, the edge's midpoint
      // and ends (sphere r 50 mm, 6 mm holes: 352 k -> 311 k triangles).
      const Vec3 &p0 = point(v), &p1 = point(kept);
      for (const Vec3& p : {w.placed[static_cast<std::size_t>(index)], Vec3(0.5 * (p0 + p1)), p1, p0}) {
        if (!shape_ok(w, c, p, before) || !distance_ok(w, c, p)) continue;
        target_[u] = c;
        target_point_[u] = p;
        Quadric q = quadric_[u];
        q += quadric_[static_cast<std::size_t>(kept)];
        w.queue.set(v, std::max(e, q.at(p)));
        return;
      }
    }
    w.queue.remove(v);
  }

  std::int32_t corner_towards(const std::vector<std::int32_t>& fan0, std::int32_t n) const {
    for (const std::int32_t c : fan0)
      if (vertex(next_corner(c)) == n) return c;
    throw std::runtime_error("mesh decimation: a fan lost a neighbour");
  }

  // The new fan around p (w.ring) from v0's fan (w.fan0) and v1's (w.fan1), less the two triangles of
  // the edge; each of its triangles no sharper than the least of `before` and the rule, and facing the
  // way the original surface does at its corners.
  bool shape_ok(Worker& w, std::int32_t c, const Vec3& p, double before) {
    const std::int32_t v0 = vertex(c), v1 = vertex(next_corner(c));
    const std::int32_t left = c / 3, right = across(previous_corner(c)) / 3;
    for (const std::int32_t k : w.fan1) before = std::min(before, sine_[static_cast<std::size_t>(k / 3)]);
    const double least = std::min(min_sine_squared_, before);
    w.ring.clear();
    w.ring_flat.clear();
    for (const auto* fan : {&w.fan0, &w.fan1})
      for (const std::int32_t k : *fan) {
        if (k / 3 == left || k / 3 == right) continue;
        const std::int32_t b = vertex(next_corner(k)), d = vertex(previous_corner(k));
        const Vec3 &pb = point(b), &pd = point(d);
        const Vec3 n = (pb - p).cross(pd - p);
        if (min_angle_sine_squared(p, pb, pd, n) < least) return false;
        const double facing = min_cos_ * n.norm();
        for (const std::int32_t x : {v0, v1, b, d})
          if (original_.normal(x).dot(n) < facing) return false;
        w.ring.push_back({b, d, k / 3, classify_triangle(p, pb, pd)});
        w.ring_flat.push_back(Flat::of(p, pb, pd));
      }
    return true;
  }

  // The squared distance from q to ring triangle i (the new vertex at p).
  double ring_distance2(const Worker& w, std::size_t i, const Vec3& p, const Vec3& q) const {
    const RingTriangle& t = w.ring[i];
    const Vec3 &b = point(t.b), &d = point(t.d);
    return (closest_point_on_triangle(q, p, b, d, t.shape) - q).squaredNorm();
  }

  // Whether q lies within the tolerance of a ring triangle.
  bool near_ring(const Worker& w, const Vec3& p, const Vec3& q, std::size_t& last) const {
    const double tolerance2 = tolerance_ * tolerance_;
    bool aside = false;  // within of a plane, the foot outside its triangle
    for (std::size_t i = 0; i < w.ring.size(); ++i) {
      const std::size_t r = (last + i) % w.ring.size();
      const int over = w.ring_flat[r].over(q, tolerance_);
      if (over == 1) {
        last = r;
        return true;
      }
      aside = aside || over < 0;
    }
    if (!aside) return false;
    for (std::size_t r = 0; r < w.ring.size(); ++r)
      if (w.ring_flat[r].over(q, tolerance_) < 0 && ring_distance2(w, r, p, q) <= tolerance2) {
        last = r;
        return true;
      }
    return false;
  }

  // Both ways, at points: the original vertices the old triangles carry, and v0's and v1's own where
  // still in place, to the new fan; the new vertex, the new triangles' centroids and the new edges'
  // midpoints to the original surface.
  bool distance_ok(Worker& w, std::int32_t c, const Vec3& p) const {
    const std::int32_t v0 = vertex(c), v1 = vertex(next_corner(c));
    std::size_t last = 0;
    for (const std::int32_t v : {v0, v1})
      if (!carried_[static_cast<std::size_t>(v)] &&
          !near_ring(w, p, samples_[static_cast<std::size_t>(v)], last))
        return false;
    const auto nv = static_cast<std::int32_t>(points_.size());
    w.under.clear();
    for (const auto* fan : {&w.fan0, &w.fan1})
      for (const std::int32_t k : *fan)
        for (std::int32_t q = first_point_[static_cast<std::size_t>(k / 3)]; q >= 0;
             q = next_point_[static_cast<std::size_t>(q)]) {
          if (!near_ring(w, p, samples_[static_cast<std::size_t>(q)], last)) return false;
          if (q >= nv) w.under.emplace_back(static_cast<std::int32_t>(last), q - nv);
        }
    w.bucket.assign(w.ring.size() + 1, 0);
    for (const auto& [r, f] : w.under) ++w.bucket[static_cast<std::size_t>(r) + 1];
    for (std::size_t r = 0; r < w.ring.size(); ++r) w.bucket[r + 1] += w.bucket[r];
    w.nearby.resize(w.under.size());
    for (const auto& [r, f] : w.under) w.nearby[w.bucket[static_cast<std::size_t>(r)]++] = f;
    for (std::size_t r = w.ring.size(); r > 0; --r) w.bucket[r] = w.bucket[r - 1];
    w.bucket[0] = 0;
    std::size_t hit = 0;
    // Near an original triangle whose centroid the old triangles carry (they lie right under the new
    // ones: most questions end there), else near the original surface by a search from the anchors.
    const auto near = [&](const Vec3& x, std::size_t ring, std::initializer_list<std::int32_t> anchors) {
      const double tolerance2 = tolerance_ * tolerance_;
      // Those under the ring triangle x lies on first, from where the last search ended.
      const std::size_t first = ring < w.ring.size() ? w.bucket[ring] : 0;
      if (hit < first || hit >= (ring < w.ring.size() ? w.bucket[ring + 1] : 0)) hit = first;
      for (std::size_t i = 0; i < w.nearby.size(); ++i) {
        const std::size_t at = (hit + i) % w.nearby.size();
        const auto f = static_cast<std::size_t>(w.nearby[at]);
        const auto& t = (*original_triangles_)[f];
        const Vec3& a = samples_[static_cast<std::size_t>(t[0])];
        if (std::abs(original_normal_[f].dot(x - a)) > tolerance_) continue;
        const Vec3& b = samples_[static_cast<std::size_t>(t[1])];
        const Vec3& d = samples_[static_cast<std::size_t>(t[2])];
        // Within of the plane (tested above): over the triangle, or near its nearest point.
        if (Flat::of(a, b, d, original_normal_[f]).foot_inside(x) ||
            (closest_point_on_triangle(x, a, b, d, original_shape_[f]) - x).squaredNorm() <= tolerance2) {
          hit = at;
          return true;
        }
      }
      return original_.near(x, anchors, tolerance_);
    };
    if (!near(p, w.ring.size(), {v0, v1})) return false;
    // The centroid, the new edge's midpoint (each new edge p -> b is the first edge of one ring
    // triangle) and the centroids of the three corner quarters: a quadratic's values at a triangle's
    // corners and midpoints alone let it stray to 1.7 times their largest in between. Each kind over
    // the whole ring before the next: a collapse that fails mostly fails at the first.
    for (int kind = 0; kind < 3; ++kind)
      for (std::size_t r = 0; r < w.ring.size(); ++r) {
        const RingTriangle& t = w.ring[r];
        const Vec3 &b = point(t.b), &d = point(t.d);
        if (kind == 0 && !near((p + b + d) / 3.0, r, {v0, v1, t.b, t.d})) return false;
        if (kind == 1 && !near(0.5 * (p + b), r, {v0, v1, t.b})) return false;
        if (kind == 2)
          for (const Vec3& x :
               {Vec3((4.0 * p + b + d) / 6.0), Vec3((p + 4.0 * b + d) / 6.0), Vec3((p + b + 4.0 * d) / 6.0)})
            if (!near(x, r, {v0, v1, t.b, t.d})) return false;
      }
    return true;
  }

  void collapse(Worker& w, std::int32_t c, const Vec3& p) {
    const std::int32_t v0 = vertex(c), v1 = vertex(next_corner(c));
    fan(v0, w.fan0);
    fan(v1, w.fan1);
    // The points the old triangles carry, and v0's and v1's own where not yet carried, go to the new fan.
    w.moved.clear();
    for (const auto* fan : {&w.fan0, &w.fan1})
      for (const std::int32_t k : *fan) {
        const auto t = static_cast<std::size_t>(k / 3);
        for (std::int32_t q = first_point_[t]; q >= 0; q = next_point_[static_cast<std::size_t>(q)])
          w.moved.push_back(q);
        first_point_[t] = -1;
      }
    for (const std::int32_t v : {v0, v1})
      if (!carried_[static_cast<std::size_t>(v)]) {
        carried_[static_cast<std::size_t>(v)] = 1;
        w.moved.push_back(v);
      }
    collapse_corners(c, w.fan0);
    w.queue.remove(v0);
    quadric_[static_cast<std::size_t>(v1)] += quadric_[static_cast<std::size_t>(v0)];
    points_[static_cast<std::size_t>(v1)] = p;

    fan(v1, w.fan_new);
    w.ring.clear();
    w.ring_flat.clear();
    for (const std::int32_t k : w.fan_new) {
      const std::int32_t bb = vertex(next_corner(k)), d = vertex(previous_corner(k));
      sine_[static_cast<std::size_t>(k / 3)] = min_angle_sine_squared(p, point(bb), point(d));
      w.ring.push_back({bb, d, k / 3, classify_triangle(p, point(bb), point(d))});
      w.ring_flat.push_back(Flat::of(p, point(bb), point(d)));
    }
    // Each to its nearest new triangle, the first in fan order among equals.
    for (const std::int32_t q : w.moved) {
      const Vec3& x = samples_[static_cast<std::size_t>(q)];
      double best = std::numeric_limits<double>::infinity();
      std::size_t nearest = 0;
      for (std::size_t i = 0; i < w.ring.size(); ++i) {
        const double plane = w.ring_flat[i].normal.dot(x - p);
        if (plane * plane > best * (1.0 + 1e-9)) continue;
        if (const double d2 = ring_distance2(w, i, p, x); d2 < best) {
          best = d2;
          nearest = i;
        }
      }
      const auto t = static_cast<std::size_t>(w.ring[nearest].old);
      next_point_[static_cast<std::size_t>(q)] = first_point_[t];
      first_point_[t] = q;
    }
  }

  std::vector<Vec3> samples_;  // the original's vertices, then its triangles' centroids
  const std::vector<Triangle>* original_triangles_ = nullptr;
  std::vector<Vec3> original_normal_;  // per original triangle, unit
  std::vector<TriangleShape> original_shape_;
  const OriginalSurface& original_;
  const double tolerance_;
  const double min_sine_squared_ = std::pow(std::sin(kMinAngleDegrees * std::numbers::pi / 180.0), 2);
  const double min_cos_ = std::cos(kMaxNormalDegrees * std::numbers::pi / 180.0);

  std::vector<Vec3> points_;  // where each vertex is now
  std::vector<Quadric> quadric_;
  std::vector<double> sine_;
  // The original vertices removed or moved, each on the list of the triangle it is nearest among those
  // it was distributed over.
  std::vector<std::int32_t> first_point_, next_point_;
  std::vector<char> carried_;         // per vertex: its original point is on a list
  std::vector<std::int32_t> target_;  // per vertex: the collapse chosen
  std::vector<Vec3> target_point_;    // and where it puts the kept vertex
};

}  // namespace

CollapsedMesh collapse_edges_placed(const TriangleMesh& mesh, const std::vector<std::int32_t>& opposite,
                                    const OriginalSurface& original, std::int64_t max_triangles,
                                    double tolerance, CollapseCounts& counts, const StageProgress& progress) {
  PlacedCollapser collapser(mesh, opposite, original, tolerance);
  collapser.run(static_cast<std::size_t>(max_triangles), counts, progress);
  return collapser.result();
}

}  // namespace poreshell
