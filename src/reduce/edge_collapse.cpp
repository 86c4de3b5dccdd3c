#include "reduce/edge_collapse.hpp"

// A corner table (each corner's vertex, and the corner across the edge it faces), error quadrics and
// a queue of vertices by error per worker, the workers on separate parts of the mesh at once. OpenMesh's
// DecimaterT made the same collapses under the same rules, on one core, in 2.3-2.6 times the time of
// one worker here; the parts on 2 cores take 0.54-0.68 of one worker's time (docs/benchmarks.md
// "Triangle reduction on flat arrays"). Where a collapse's distance from the original follows from
// the triangles around it (fan_distance_bound()), it asks the original surface nothing: on the bunny
// that settles 70 % of the collapses and takes the reduction's time to 0.84 of the checks alone
// (bench_reduce --compare; docs/benchmarks.md "Bounds from the fans").

#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>

#include <Eigen/Geometry>  // cross()
#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <memory>
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
constexpr double kUnbounded = std::numeric_limits<double>::infinity();
// Slack in the barycentric test of a point on a triangle's edge, lest round-off miss both triangles.
constexpr double kOnEdge = 1e-12;

// A collapse is named by the corner c of v0 in the triangle that runs v0 -> v1 -> vl; the triangle
// across the edge runs v1 -> v0 -> vr.
//
// The collapses run as workers, each on its own part of the mesh: a worker moves only vertices it
// owns (owner_ is its part), and a vertex is owned only where all its neighbours are in the same part.
// A collapse reads and writes the triangles around v0 and v1 and those across their outer edges,
// all of whose vertices are then in the part: the parts' collapses touch disjoint data and may run at
// once. The vertices along the cuts between parts belong to none; a last worker owning every vertex
// goes on from there to the target (see run()).
class Collapser : CornerTable {
 public:
  Collapser(const TriangleMesh& mesh, const std::vector<std::int32_t>& opposite,
            const OriginalSurface& original, double tolerance, DistanceRule rule)
      : points_(mesh.vertices), original_(original), tolerance_(tolerance), rule_(rule) {
    const std::size_t nv = mesh.vertices.size(), nf = mesh.triangles.size();
    // The quadrics' sums run on one thread beside the rest, in triangle order: the same sums on any
    // thread count. The arrays (160 MB on the bunny's 1.5 M-triangle shell) are filled in the branches
    // too, so that their first touch is shared out as well (0.14 s -> 0.10-0.12 s).
    tbb::parallel_invoke(
        [&] {
          first_point_.assign(nf, -1);
          next_point_.assign(nv, -1);
          owner_.assign(nv, 0);
          bound_.assign(nv, 0.0);
          checked_.assign(nv, 0);
          shapes_refuse_.assign(nv, 0);
          target_.assign(nv, -1);
          distance_bound_.assign(nf, 0.0);
          target_bound_.assign(nv, kUnbounded);
        },
        [&] { quadric_ = vertex_quadrics(mesh); },
        [&] {
          build_table(mesh, opposite);
          sine_.resize(nf);
          shape_.resize(nf);
          tbb::parallel_for(std::size_t{0}, mesh.triangles.size(), [&](std::size_t f) {
            const auto& t = mesh.triangles[f];
            const Vec3 &a = points_[t[0]], &b = points_[t[1]], &c = points_[t[2]];
            sine_[f] = min_angle_sine_squared(a, b, c);
            shape_[f] = classify_triangle(a, b, c);
          });
        });
  }

  void run(std::size_t target, CollapseCounts& counts, const StageProgress& progress) {
    run_in_parts(
        points_, target, kAsLeft, counts, progress,
        [&](int part, std::size_t questions) { return Worker(part, points_.size(), questions); },
        [&](Worker& w, std::size_t quota, const std::vector<char>& candidate, LoopProgress& loop) {
          return collapse_until(w, quota, candidate, loop);
        });
  }

  CollapsedMesh result() const { return live_mesh(first_point_, next_point_, points_.size()); }

 private:
  static constexpr char kAsLeft = 2;  // a candidate for the last worker with its part's rating

  // A triangle the collapse makes, its first corner where v0 was (now v1).
  using NewTriangle = std::array<std::int32_t, 3>;

  // A point seen along a fan's normal: where across it, and the height along it, from the fan's centre.
  struct Projected {
    double x, y, h;
  };
  // The z of the cross product of two points seen across a fan: positive where b is left of a.
  static double cross(const Projected& a, const Projected& b) { return a.x * b.y - a.y * b.x; }

  // v0's fan as fan_distance_bound() sees it (see_fan()).
  struct FanFrame {
    bool ready = false, usable = false;
    Vec3 p0, normal, ex, ey;
    double old_bound = 0.0;

    Projected seen(const Vec3& p) const {
      const Vec3 d = p - p0;
      return {ex.dot(d), ey.dot(d), normal.dot(d)};
    }
  };

  // A new triangle's unit normal (zero where it has no area) and shape.
  struct Plane {
    Vec3 normal;
    TriangleShape shape;

    static Plane of(const Vec3& a, const Vec3& b, const Vec3& c, TriangleShape shape) {
      return {shape == TriangleShape::degenerate ? Vec3::Zero() : (b - a).cross(c - a).stableNormalized(),
              shape};
    }
  };

  // What one sequence of collapses keeps for itself.
  struct Worker {
    // `questions`: about how many distinct ones the cache should hold (NearCache).
    Worker(int owned_part, std::size_t vertices, std::size_t questions)
        : part(owned_part), queue(vertices), mark(vertices, 0), cache(questions) {}
    int part;
    VertexQueue<> queue;
    std::vector<std::uint32_t> mark;  // stamp on v0's neighbours during a link test
    std::uint32_t stamp = 0;
    NearCache cache;
    // Scratch, kept to save allocations.
    std::vector<std::int32_t> scratch, fan_rated, fan_check, fan_kept, moved;
    std::vector<std::int32_t> moved_from;  // each moved point's place in fan_kept before, or -1
    std::vector<char> changed;             // per place in fan_kept: the triangle was v0's
    std::vector<std::int32_t> were_v0s;    // the kept vertex's neighbours that were v0's
    std::vector<std::tuple<double, std::int32_t, std::int32_t>> candidates;  // (error, v1, corner)
    std::vector<NewTriangle> ring;
    std::vector<Plane> ring_planes;  // of ring's triangles in hausdorff_ok(), of fan_kept's in collapse()
    std::vector<Projected> spokes;
    FanFrame frame;  // of v0's fan, for fan_distance_bound(); ready once seen in this choose()
    CollapseCounts counts;
  };

  // The worker's collapses, starting from the candidate vertices it owns, until `quota` triangles are
  // gone or none of its vertices can move; returns how many triangles went.
  std::size_t collapse_until(Worker& w, std::size_t quota, const std::vector<char>& candidate,
                             LoopProgress& loop) {
    for (std::size_t v = 0; v < points_.size(); ++v) {
      if (!candidate[v] || vertex_corner_[v] < 0 || !owns(w, static_cast<std::int32_t>(v))) continue;
      if (candidate[v] == kAsLeft)
        w.queue.set(static_cast<std::int32_t>(v), checked_[v] ? error(target_[v]) : bound_[v]);
      else
        rate(w, static_cast<std::int32_t>(v));
    }
    std::size_t removed = 0, unreported = 0;
    std::int32_t just_chosen = -1;  // its collapse passed the link test on the mesh as it still is
    while (removed < quota && !w.queue.empty()) {
      const std::int32_t v = w.queue.top();
      const auto u = static_cast<std::size_t>(v);
      if (!checked_[u] || vertex(target_[u]) != v || (v != just_chosen && !topology_ok(w, target_[u]))) {
        choose(w, v);
        just_chosen = v;
        continue;
      }
      just_chosen = -1;
      const std::int32_t kept = vertex(next_corner(target_[u]));
      ++(target_bound_[u] == kUnbounded ? w.counts.checked : w.counts.bounded);
      collapse(w, target_[u]);
      removed += 2;
      // Every vertex whose collapses the change could touch is next to the kept one. Those that were
      // next to v0 too have new triangles: their collapses are rated again. Their errors only grow
      // (the kept vertex's quadric did), but for the collapse onto the kept vertex, new where it was
      // next to v0 alone: that one lowers the bound, if any. The others' triangles, and the points on
      // them (collapse()), are as they were, so their collapses pass or fail as before; only the one
      // onto the kept vertex has a larger error, and a vertex that had chosen it chooses again.
      rate(w, kept, w.fan_kept);  // collapse() left the kept vertex's fan there
      w.were_v0s.clear();
      for (std::size_t i = 0; i < w.fan_kept.size(); ++i)
        if (w.changed[i]) {
          w.were_v0s.push_back(vertex(next_corner(w.fan_kept[i])));
          w.were_v0s.push_back(vertex(previous_corner(w.fan_kept[i])));
        }
      for (const std::int32_t c : w.fan_kept) {
        const std::int32_t n = vertex(next_corner(c));
        const auto x = static_cast<std::size_t>(n);
        if (!owns(w, n) || shapes_refuse_[x]) continue;
        if (std::find(w.were_v0s.begin(), w.were_v0s.end(), n) != w.were_v0s.end()) {
          bound_[x] = std::min(bound_[x], error(n, kept));
          checked_[x] = 0;
          w.queue.set(n, bound_[x]);
        } else if (checked_[x] && vertex(next_corner(target_[x])) == kept) {
          checked_[x] = 0;
          w.queue.set(n, bound_[x]);
        }
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

  // The link condition: v0 and v1 share no neighbour but vl and vr. A valence-3 vertex beside the
  // edge would be left with two triangles back to back.
  bool topology_ok(Worker& w, std::int32_t c) {
    if (c < 0 || dead_[static_cast<std::size_t>(c / 3)]) return false;
    mark_neighbours(w, vertex(c));
    return link_ok(w, c);
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
  bool link_ok(Worker& w, std::int32_t c) const {
    return CornerTable::link_ok(c, w.mark, w.stamp, w.scratch);
  }
  void mark_neighbours(Worker& w, std::int32_t v) {
    fan(v, w.fan_rated);
    ++w.stamp;
    for (const std::int32_t c : w.fan_rated)
      w.mark[static_cast<std::size_t>(vertex(next_corner(c)))] = w.stamp;
  }

  // The least error of v's collapses: a lower bound on the collapse choose() would make, which is
  // all the queue needs until v comes to its top (so the link condition, which costs a walk around
  // each neighbour, waits until then too).
  void rate(Worker& w, std::int32_t v) {
    fan(v, w.fan_rated);
    rate(w, v, w.fan_rated);
  }
  void rate(Worker& w, std::int32_t v, const std::vector<std::int32_t>& corners) {
    const auto u = static_cast<std::size_t>(v);
    checked_[u] = 0;
    bound_[u] = std::numeric_limits<double>::infinity();
    for (const std::int32_t c : corners) bound_[u] = std::min(bound_[u], error(c));
    w.queue.set(v, bound_[u]);
  }

  // v's least-error collapse onto a vertex the worker owns that passes all the rules, or none: v
  // leaves the queue until a collapse next to it rates it again.
  void choose(Worker& w, std::int32_t v) {
    const auto u = static_cast<std::size_t>(v);
    mark_neighbours(w, v);
    w.candidates.clear();
    for (const std::int32_t c : w.fan_rated) w.candidates.emplace_back(error(c), vertex(next_corner(c)), c);
    std::sort(w.candidates.begin(), w.candidates.end());  // ties by the kept vertex: deterministic
    bound_[u] = std::get<0>(w.candidates.front());
    w.fan_check = w.fan_rated;  // the checks' copy of v0's fan
    w.frame.ready = false;
    double before = 1.0;
    for (const std::int32_t k : w.fan_check)
      before = std::min(before, sine_[static_cast<std::size_t>(k / 3)]);
    const double least = std::min(min_sine_squared_, before);
    bool only_shapes = true;  // every candidate so far refused by its shape alone
    for (const auto& [e, kept, c] : w.candidates) {
      // The shapes first: they refuse most candidates (on the bunny 2.5 M of 4 M) and read only v0's
      // neighbours, which the link test would walk around v1 for.
      if (!owns(w, kept)) {
        only_shapes = false;
        continue;
      }
      if (!shape_ok(w, c, least)) continue;
      only_shapes = false;
      if (!link_ok(w, c)) continue;
      // The bound where it follows from the fans alone; else the checks against the original.
      const double bound = rule_ == DistanceRule::kCheckOnly ? kUnbounded : fan_distance_bound(w, c);
      if (bound == kUnbounded && (rule_ == DistanceRule::kBoundOnly || !hausdorff_ok(w, c) || !near_ok(w)))
        continue;
      target_bound_[u] = bound;
      checked_[u] = 1;
      target_[u] = c;
      w.queue.set(v, e);
      return;
    }
    checked_[u] = 0;
    shapes_refuse_[u] = only_shapes ? 1 : 0;
    w.queue.remove(v);
  }

  // Angles and normals of the triangles the collapse changes; keeps them in the worker's ring for
  // the checks after.
  bool shape_ok(Worker& w, std::int32_t c, double least) {
    const std::int32_t v1 = vertex(next_corner(c));
    const std::int32_t left = c / 3, right = across(previous_corner(c)) / 3;
    w.ring.clear();
    for (const std::int32_t k : w.fan_check) {
      if (k / 3 == left || k / 3 == right) continue;  // removed by the collapse
      const NewTriangle t{v1, vertex(next_corner(k)), vertex(previous_corner(k))};
      const Vec3 &a = point(t[0]), &b = point(t[1]), &d = point(t[2]);
      const Vec3 n = (b - a).cross(d - a);
      if (min_angle_sine_squared(a, b, d, n) < least) return false;
      const double facing = min_cos_ * n.norm();
      for (const std::int32_t x : t)
        if (original_.normal(x).dot(n) < facing) return false;
      w.ring.push_back(t);
    }
    return true;
  }

  // A bound on how far the triangles the collapse makes can be from the original surface, both ways,
  // that needs no question to it, or kUnbounded. Seen along the old fan's normal, the old fan
  // around v0 and the new one around v1 cover the same polygon, v0's link, once each where all their
  // triangles face that way and the link winds once around v0: each point of one fan then has one
  // of the other straight across, and the two are as far apart as the heights of two piecewise
  // linear functions over the polygon, greatest where v0 lies or where an edge of one crosses an
  // edge of the other. Add the old triangles' own bounds.
  double fan_distance_bound(Worker& w, std::int32_t c) const {
    FanFrame& f = w.frame;
    if (!f.ready) see_fan(w, vertex(c));
    if (!f.usable) return kUnbounded;
    double gap = 0.0;
    bool covers_v0 = false;
    for (const NewTriangle& t : w.ring) {
      const Projected a = f.seen(point(t[0])), b = f.seen(point(t[1])), d = f.seen(point(t[2]));
      const Projected ab{b.x - a.x, b.y - a.y, b.h - a.h}, ad{d.x - a.x, d.y - a.y, d.h - a.h};
      const double twice_area = cross(ab, ad);
      if (!(twice_area > 0.0)) return kUnbounded;
      // v0's barycentric coordinates in the new triangle.
      const double wb = cross(d, a) / twice_area, wd = cross(a, b) / twice_area;
      if (wb >= -kOnEdge && wd >= -kOnEdge && wb + wd <= 1.0 + kOnEdge) {
        covers_v0 = true;
        gap = std::max(gap, std::abs(a.h + wb * ab.h + wd * ad.h));
      }
      // The new edge a -> d (from v1; every inner one is one of these) across each spoke p0 -> s:
      // u s = a + v ad.
      const double a_across = cross(a, ad);
      for (const Projected& s : w.spokes) {
        const double det = cross(s, ad);
        if (det == 0.0) continue;
        const double u = a_across / det, v = cross(a, s) / det;
        if (u > 0.0 && u < 1.0 && v > 0.0 && v < 1.0) gap = std::max(gap, std::abs(a.h + v * ad.h - u * s.h));
      }
    }
    const double bound = gap + f.old_bound;
    return covers_v0 && bound <= tolerance_ ? bound : kUnbounded;
  }

  // What fan_distance_bound() needs of v0's fan alone, the same for each of its collapses: the fan's
  // normal and a frame across it, the spokes seen in it, the old triangles' largest bound, and whether
  // the fan is seen once around v0 at all. Where that bound alone is over the tolerance, the rest is
  // not needed.
  void see_fan(Worker& w, std::int32_t v0) const {
    FanFrame& f = w.frame;
    f.ready = true;
    f.usable = false;
    f.old_bound = 0.0;
    for (const std::int32_t k : w.fan_check)
      f.old_bound = std::max(f.old_bound, distance_bound_[static_cast<std::size_t>(k / 3)]);
    if (f.old_bound > tolerance_) return;
    f.p0 = point(v0);
    f.normal = Vec3::Zero();
    for (const std::int32_t k : w.fan_check)
      f.normal += (point(vertex(next_corner(k))) - f.p0).cross(point(vertex(previous_corner(k))) - f.p0);
    if (!(f.normal.norm() > 0.0)) return;
    f.normal.normalize();
    f.ex = f.normal.unitOrthogonal();
    f.ey = f.normal.cross(f.ex);
    int windings = 0;
    w.spokes.clear();
    for (const std::int32_t k : w.fan_check) {
      const Projected a = f.seen(point(vertex(next_corner(k)))),
                      b = f.seen(point(vertex(previous_corner(k))));
      if (!(cross(a, b) > 0.0)) return;
      // Turning left by less than half a turn, from below the x axis to above it crosses its
      // positive half: the crossings count the windings.
      windings += a.y < 0.0 && b.y >= 0.0;
      w.spokes.push_back(a);
    }
    f.usable = windings == 1;
  }

  // Each new edge is the edge from v1 onwards of one new triangle.
  bool near_ok(Worker& w) const {
    for (const NewTriangle& t : w.ring) {
      const std::int32_t a = t[0], b = t[1], d = t[2];  // not a structured binding: lambdas use them
      const Vec3 centroid = (point(a) + point(b) + point(d)) / 3.0;
      if (!w.cache.get(a, b, d, [&] {
            return near_old_fan(w, centroid) || original_.near(centroid, {a, b, d}, tolerance_);
          }))
        return false;
      const Vec3 midpoint = 0.5 * (point(a) + point(b));
      if (!w.cache.get(a, b, -1, [&] {
            return near_old_fan(w, midpoint) || original_.near(midpoint, {a, b}, tolerance_);
          }))
        return false;
    }
    return true;
  }

  // Whether p is within the tolerance of the original surface by way of a triangle around v0 whose
  // own bound is known: the original surface is within that bound of every point of it. Where it
  // says so, OriginalSurface::near() would too, but it starts from the anchors' triangles and walks,
  // where these lie right under p. On the bunny it settles half of the questions; bench_reduce with
  // and without it in turn: 6.81-7.37 s against 6.82-7.74 s.
  bool near_old_fan(const Worker& w, const Vec3& p) const {
    for (const std::int32_t k : w.fan_check) {
      const double bound = distance_bound_[static_cast<std::size_t>(k / 3)];
      if (!(bound < tolerance_)) continue;
      const double reach = tolerance_ - bound;
      const Vec3 q = closest_point_on_triangle(p, point(vertex(k)), point(vertex(next_corner(k))),
                                               point(vertex(previous_corner(k))),
                                               shape_[static_cast<std::size_t>(k / 3)]);
      if ((q - p).squaredNorm() <= reach * reach) return true;
    }
    return false;
  }

  // The vertex removed and the original vertices removed before, on the triangles around it, each
  // within the tolerance of one of the new triangles. A triangle whose plane is further is passed
  // over, and the search starts at the triangle the point before was near: removed points lie in
  // runs along the surface, and the fans have up to some tens of them.
  bool hausdorff_ok(Worker& w, std::int32_t c) const {
    const double tolerance2 = tolerance_ * tolerance_, plane_slack = tolerance_ * (1.0 + 1e-9);
    w.ring_planes.clear();
    for (const NewTriangle& t : w.ring) {
      const Vec3 &a = point(t[0]), &b = point(t[1]), &d = point(t[2]);
      w.ring_planes.push_back(Plane::of(a, b, d, classify_triangle(a, b, d)));
    }
    std::size_t last = 0;
    const auto within = [&](const Vec3& p) {
      for (std::size_t i = 0; i < w.ring.size(); ++i) {
        const std::size_t r = (last + i) % w.ring.size();
        const NewTriangle& t = w.ring[r];
        const Vec3& a = point(t[0]);
        if (std::abs(w.ring_planes[r].normal.dot(p - a)) > plane_slack) continue;
        if ((closest_point_on_triangle(p, a, point(t[1]), point(t[2]), w.ring_planes[r].shape) - p)
                .squaredNorm() <= tolerance2) {
          last = r;
          return true;
        }
      }
      return false;
    };
    if (!within(point(vertex(c)))) return false;
    for (const std::int32_t k : w.fan_check)
      for (std::int32_t p = first_point_[static_cast<std::size_t>(k / 3)]; p >= 0;
           p = next_point_[static_cast<std::size_t>(p)])
        if (!within(point(p))) return false;
    return true;
  }

  void collapse(Worker& w, std::int32_t c) {
    const std::int32_t v0 = vertex(c), v1 = vertex(next_corner(c));
    const std::int32_t left = c / 3, right = across(previous_corner(c)) / 3;
    fan(v0, w.fan_check);
    // Their fans change: v0's neighbours' triangles now end at v1 (vl's and vr's lose one), v1's grows.
    for (const std::int32_t k : w.fan_check)
      shapes_refuse_[static_cast<std::size_t>(vertex(next_corner(k)))] = 0;
    shapes_refuse_[static_cast<std::size_t>(v1)] = 0;
    for (const std::int32_t k : w.fan_check)
      if (k / 3 != left && k / 3 != right)
        distance_bound_[static_cast<std::size_t>(k / 3)] = target_bound_[static_cast<std::size_t>(v0)];
    collapse_corners(c, w.fan_check);
    w.queue.remove(v0);
    quadric_[static_cast<std::size_t>(v1)] += quadric_[static_cast<std::size_t>(v0)];

    // The changed triangles' shapes and planes: a triangle whose plane is no nearer to a point than
    // the nearest so far cannot be nearer itself (below).
    fan(v1, w.fan_kept);
    w.ring_planes.clear();
    w.changed.clear();
    for (const std::int32_t k : w.fan_kept) {
      // v1's triangles from before keep their corners: only v0's, now v1's, changed.
      const bool changed =
          std::any_of(w.fan_check.begin(), w.fan_check.end(), [&](std::int32_t j) { return j / 3 == k / 3; });
      w.changed.push_back(changed);
      if (!changed) {
        w.ring_planes.push_back({Vec3::Zero(), TriangleShape::degenerate});  // takes no points (below)
        continue;
      }
      const auto t = static_cast<std::size_t>(k / 3);
      const Vec3 &c0 = point(corners_[3 * t].vertex), &c1 = point(corners_[3 * t + 1].vertex),
                 &c2 = point(corners_[3 * t + 2].vertex);
      sine_[t] = min_angle_sine_squared(c0, c1, c2);
      shape_[t] = classify_triangle(c0, c1, c2);
      w.ring_planes.push_back(Plane::of(c0, c1, c2, shape_[t]));
    }
    // The removed vertices on the changed triangles, and v0, each go to the nearest changed triangle.
    w.moved.clear();
    w.moved_from.clear();
    const auto take = [&](std::int32_t t, std::int32_t from) {
      for (std::int32_t p = first_point_[static_cast<std::size_t>(t)]; p >= 0;
           p = next_point_[static_cast<std::size_t>(p)]) {
        w.moved.push_back(p);
        w.moved_from.push_back(from);
      }
      first_point_[static_cast<std::size_t>(t)] = -1;
    };
    take(left, -1);
    take(right, -1);
    // A point on one of v1's triangles from before keeps it: its distance to it, which bounds its
    // distance to the surface, has not changed, and the checks ask about it once that triangle changes.
    // So the triangles from before keep their points, and their vertices' collapses stay as they were
    // rated (collapse_until()).
    for (std::size_t i = 0; i < w.fan_kept.size(); ++i)
      if (w.changed[i]) take(w.fan_kept[i] / 3, static_cast<std::int32_t>(i));
    w.moved.push_back(v0);
    w.moved_from.push_back(-1);
    const auto first_changed =
        static_cast<std::size_t>(std::find(w.changed.begin(), w.changed.end(), 1) - w.changed.begin());
    // The nearest triangle, the first in fan order among equals. A point's own triangle, where it is still
    // there, goes first: mostly the nearest still, it lets the planes rule out most of the others.
    const auto distance2_to = [&](std::int32_t p, std::size_t i) {
      const std::int32_t t = w.fan_kept[i] / 3;
      return (closest_point_on_triangle(point(p), point(vertex(3 * t)), point(vertex(3 * t + 1)),
                                        point(vertex(3 * t + 2)), w.ring_planes[i].shape) -
              point(p))
          .squaredNorm();
    };
    for (std::size_t m = 0; m < w.moved.size(); ++m) {
      const std::int32_t p = w.moved[m], from = w.moved_from[m];
      double best = from >= 0 ? distance2_to(p, static_cast<std::size_t>(from))
                              : std::numeric_limits<double>::infinity();
      std::size_t nearest_at = from >= 0 ? static_cast<std::size_t>(from) : first_changed;
      for (std::size_t i = 0; i < w.fan_kept.size(); ++i) {
        if (!w.changed[i] || static_cast<std::int32_t>(i) == from) continue;
        const double plane = w.ring_planes[i].normal.dot(point(p) - point(vertex(w.fan_kept[i] / 3 * 3)));
        if (plane * plane > best * (1.0 + 1e-9)) continue;
        if (const double d2 = distance2_to(p, i); d2 < best || (d2 == best && i < nearest_at)) {
          best = d2;
          nearest_at = i;
        }
      }
      const std::int32_t nearest = w.fan_kept[nearest_at] / 3;
      next_point_[static_cast<std::size_t>(p)] = first_point_[static_cast<std::size_t>(nearest)];
      first_point_[static_cast<std::size_t>(nearest)] = p;
    }
  }

  const std::vector<Vec3>& points_;
  const OriginalSurface& original_;
  const double tolerance_;
  const DistanceRule rule_;
  const double min_sine_squared_ = std::pow(std::sin(kMinAngleDegrees * std::numbers::pi / 180.0), 2);
  const double min_cos_ = std::cos(kMaxNormalDegrees * std::numbers::pi / 180.0);

  std::vector<Quadric> quadric_;      // per vertex
  std::vector<double> sine_;          // squared, of each triangle's smallest angle, kept up to date
  std::vector<TriangleShape> shape_;  // of each triangle, kept up to date
  // The removed vertices, each on the list of the triangle it is nearest among those it was
  // distributed over: first_point_ per triangle, next_point_ per vertex, -1 ends a list.
  std::vector<std::int32_t> first_point_, next_point_;
  std::vector<double> bound_;  // per vertex: at most the error of each of its collapses
  std::vector<char> checked_;  // target_ passed all the rules and the queue holds its error
  // Per vertex: every collapse of it failed its shape on its fan as it is. A shape depends on the fan
  // alone, so the vertex stays out of the queue until its fan changes.
  std::vector<char> shapes_refuse_;
  std::vector<std::int32_t> target_;  // per vertex: the collapse chosen
  // Per triangle: at most its distance from the original surface, both ways, as far as
  // fan_distance_bound() can tell; kUnbounded where the checks at points against it passed instead.
  std::vector<double> distance_bound_;
  std::vector<double> target_bound_;  // per vertex: fan_distance_bound() of target_
};

}  // namespace

CollapsedMesh collapse_edges(const TriangleMesh& mesh, const std::vector<std::int32_t>& opposite,
                             const OriginalSurface& original, std::int64_t max_triangles, double tolerance,
                             DistanceRule rule, CollapseCounts& counts, const StageProgress& progress) {
  Collapser collapser(mesh, opposite, original, tolerance, rule);
  collapser.run(static_cast<std::size_t>(max_triangles), counts, progress);
  return collapser.result();
}

}  // namespace poreshell
