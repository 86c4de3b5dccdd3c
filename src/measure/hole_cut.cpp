#include "measure/hole_cut.hpp"

// One pass over the triangles finds, for every seed, those that cross its cut within its reach (the
// seeds are hashed into cells, as the wall probes' rays are), so no search tree over a mesh of millions
// of triangles is built. Each seed's crossings are then chained into loops through the mesh's edges,
// matched by vertex indices rather than positions, so every loop of a closed mesh closes exactly.

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>  // cross()
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <unordered_map>
#include <unordered_set>
#include <utility>

#include "core/cell_hash.hpp"

namespace poreshell {
namespace {

constexpr std::int64_t kMaxCellsPerTriangle = 64;  // larger triangles are tested against every seed

constexpr std::size_t kRings = 4, kAngles = 16;  // the cut's samples of the wall's middle about a seed
// Queries moved by their miss per sample (see CutSurface::sample): on the bunny (8 mm holes, 2 mm wall)
// 0, 1, 2, 3 left 45, 29, 26, 25 seeds without a loop; 4 x 16 samples left as many as 8 x 32.
constexpr int kLateralIterations = 2;
constexpr int kTraceStarts = 8;  // crossings of the model cut a trace starts from

// The surface a seed's hole is cut with: the wall's middle as heights over a plane through the seed,
// sampled on rings out to the seed's reach and interpolated bilinearly in radius and angle (constant
// beyond the last ring); the plane itself without samples. A tangent plane leaves a 2 mm wall within
// 4 mm of the axis where the wall curves with a radius under 8 mm, as on much of the bunny. The plane's
// normal, the hole's axis, is fitted to the samples within half the reach: a scan's facets tilt the
// surface normal at the seed by 10 degrees and more from the hole's.
class CutSurface {
 public:
  CutSurface(const HoleSeed& seed, const MidWall* mid_wall) : seed_(seed) {
    set_frame(seed.normal);
    ring_ = seed.reach / kRings;
    if (!mid_wall || !(ring_ > 0.0)) return;
    points_[0].fill(seed.point);
    sample(*mid_wall);
    // The hole's axis: the normal of the plane through the samples within half the reach (one refit
    // took 2 more of the bunny's seeds to a loop, a second 1 more).
    Vec3 mean = Vec3::Zero();
    for (std::size_t k = 0; k <= kRings / 2; ++k)
      for (const Vec3& m : points_[k]) mean += m;
    mean /= static_cast<double>((kRings / 2 + 1) * kAngles);
    Eigen::Matrix3d spread = Eigen::Matrix3d::Zero();
    for (std::size_t k = 0; k <= kRings / 2; ++k)
      for (const Vec3& m : points_[k]) spread += (m - mean) * (m - mean).transpose();
    Vec3 n = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(spread).eigenvectors().col(0).normalized();
    if (n.allFinite()) {
      set_frame(n.dot(seed.normal) < 0.0 ? Vec3(-n) : n);
      sample(*mid_wall);
    }
    // Points farther than this from the samples' range need no interpolation to tell their side.
    margin_ = 1e-9 * (seed.reach + hi_ - lo_);
    for (std::size_t k = 0; k <= kRings; ++k)
      for (std::size_t q = 0; q < 4; ++q) {
        double lo = height_[k][q * kAngles / 4], hi = lo;
        for (const std::size_t ring : {k, std::min(k + 1, kRings)})
          for (std::size_t j = q * kAngles / 4; j <= (q + 1) * kAngles / 4; ++j) {
            lo = std::min(lo, height_[ring][j % kAngles]);
            hi = std::max(hi, height_[ring][j % kAngles]);
          }
        sector_[k][q] = {lo - margin_, hi + margin_};
      }
  }

  const HoleSeed& seed() const { return seed_; }

  // Height of x above the cut along the normal; >= 0 counts as above, so that every crossed edge has
  // one end on each side and both its triangles agree.
  double height(const Vec3& x) const {
    const Vec3 d = x - seed_.point;
    return seed_.normal.dot(d) - cut_height(d.dot(u_), d.dot(v_));
  }
  // height(x) >= 0, told without interpolating where x lies above or below every sample of its
  // sector (between two rings, in a quarter turn): most of a solid's faces near a hole.
  bool above(const Vec3& x) const {
    const Vec3 d = x - seed_.point;
    const double z = seed_.normal.dot(d);
    if (z > hi_ + margin_) return true;
    if (z < lo_ - margin_) return false;
    const double a = d.dot(u_), b = d.dot(v_);
    const auto k = static_cast<std::size_t>(std::min(std::sqrt(a * a + b * b) / ring_, double{kRings}));
    const auto& [lo, hi] = sector_[k][b >= 0.0 ? (a >= 0.0 ? 0 : 1) : (a < 0.0 ? 2 : 3)];
    if (z > hi) return true;
    if (z < lo) return false;
    return z - cut_height(a, b) >= 0.0;
  }
  // Coordinates in the plane, and the cut's point over them.
  Eigen::Vector2d plane(const Vec3& x) const {
    const Vec3 d = x - seed_.point;
    return {d.dot(u_), d.dot(v_)};
  }
  Vec3 lift(const Eigen::Vector2d& q) const {
    return seed_.point + q.x() * u_ + q.y() * v_ + cut_height(q.x(), q.y()) * seed_.normal;
  }

 private:
  void set_frame(const Vec3& n) {
    seed_.normal = n;
    Eigen::Index least = 0;
    n.cwiseAbs().minCoeff(&least);
    u_ = n.cross(Vec3::Unit(least)).normalized();  // from the axis farthest from the normal
    v_ = n.cross(u_);
  }

  void sample(const MidWall& mid_wall) {
    const Vec3& n = seed_.normal;
    lo_ = hi_ = 0.0;
    for (std::size_t k = 1; k <= kRings; ++k)
      for (std::size_t j = 0; j < kAngles; ++j) {
        const double a = 2.0 * std::numbers::pi * static_cast<double>(j) / kAngles;
        const Vec3 q = seed_.point + static_cast<double>(k) * ring_ * (std::cos(a) * u_ + std::sin(a) * v_);
        std::optional<Vec3> m = mid_wall.point(q, n);
        // On a slope the nearest point lies off q's line along the normal: move the query by the miss.
        for (int i = 0; i < kLateralIterations && m; ++i) {
          const Vec3 miss = (q - *m) - n.dot(q - *m) * n;
          m = mid_wall.point(*m + miss, n);
        }
        // Where the wall's middle has no point, the ring inside it stands in.
        points_[k][j] = m ? *m : points_[k - 1][j] + (q - seed_.point) / static_cast<double>(k);
        height_[k][j] = m ? n.dot(*m - seed_.point) : height_[k - 1][j];
        lo_ = std::min(lo_, height_[k][j]);
        hi_ = std::max(hi_, height_[k][j]);
      }
  }

  double cut_height(double a, double b) const {
    if (lo_ == hi_) return lo_;  // flat
    double t = std::atan2(b, a) * (kAngles / (2.0 * std::numbers::pi));
    if (t < 0.0) t += kAngles;
    const double w = t - std::floor(t);
    const std::size_t j0 = static_cast<std::size_t>(std::floor(t)) % kAngles, j1 = (j0 + 1) % kAngles;
    const auto around = [&](std::size_t k) { return (1.0 - w) * height_[k][j0] + w * height_[k][j1]; };
    const double r = std::sqrt(a * a + b * b) / ring_;
    if (!(r < kRings)) return around(kRings);
    const auto k0 = static_cast<std::size_t>(std::floor(r));
    const double s = r - static_cast<double>(k0);
    return (1.0 - s) * around(k0) + s * around(k0 + 1);
  }

  HoleSeed seed_;
  Vec3 u_ = Vec3::UnitX(), v_ = Vec3::UnitY();
  double ring_ = 0.0;
  std::array<std::array<double, kAngles>, kRings + 1> height_{};  // ring 0: the seed, height 0
  std::array<std::array<Vec3, kAngles>, kRings + 1> points_{};    // the samples (ring 0: the seed)
  double lo_ = 0.0, hi_ = 0.0, margin_ = 0.0;
  // Bounds of the cut's height between rings k and k + 1 in each quarter turn, widened by the margin.
  std::array<std::array<std::pair<double, double>, 4>, kRings + 1> sector_{};
};

// Seeds registered in every cell their reach's box meets, cells as large as the largest reach.
CellHash seed_cells(std::span<const CutSurface> cuts) {
  double reach = 0.0;
  for (const CutSurface& c : cuts) reach = std::max(reach, c.seed().reach);
  CellHash cells(reach > 0.0 ? reach : 1.0);
  for (std::size_t s = 0; s < cuts.size(); ++s) {
    const double r = cuts[s].seed().reach;
    if (!(r > 0.0)) continue;
    cells.add_box(cuts[s].seed().point - Vec3::Constant(r), cuts[s].seed().point + Vec3::Constant(r),
                  static_cast<std::uint32_t>(s));
  }
  cells.seal();
  return cells;
}

// Per seed, the triangles that cross its cut and whose boxes meet its reach, in index order.
std::vector<std::vector<std::uint32_t>> crossing_triangles(const TriangleMesh& mesh,
                                                           std::span<const CutSurface> cuts) {
  const CellHash cells = seed_cells(cuts);
  tbb::enumerable_thread_specific<std::vector<std::uint64_t>> found;  // seed << 32 | triangle
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, mesh.triangles.size(), 4096),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      std::vector<std::uint64_t>& out = found.local();
                      for (std::size_t f = range.begin(); f != range.end(); ++f) {
                        const auto& t = mesh.triangles[f];
                        const Vec3& a = mesh.vertices[static_cast<std::size_t>(t[0])];
                        const Vec3& b = mesh.vertices[static_cast<std::size_t>(t[1])];
                        const Vec3& c = mesh.vertices[static_cast<std::size_t>(t[2])];
                        const Vec3 lo = a.cwiseMin(b).cwiseMin(c), hi = a.cwiseMax(b).cwiseMax(c);
                        const auto test = [&](std::uint32_t s) {
                          const CutSurface& cut = cuts[s];
                          const HoleSeed& seed = cut.seed();
                          const Vec3 gap = (lo - seed.point).cwiseMax(seed.point - hi).cwiseMax(0.0);
                          if (!(gap.squaredNorm() <= seed.reach * seed.reach)) return;
                          const bool up = cut.above(a);
                          if (cut.above(b) == up && cut.above(c) == up) return;
                          out.push_back((std::uint64_t{s} << 32) | f);
                        };
                        const std::int64_t i0 = cells.cell_of(lo.x()), i1 = cells.cell_of(hi.x());
                        const std::int64_t j0 = cells.cell_of(lo.y()), j1 = cells.cell_of(hi.y());
                        const std::int64_t k0 = cells.cell_of(lo.z()), k1 = cells.cell_of(hi.z());
                        if ((i1 - i0 + 1) * (j1 - j0 + 1) * (k1 - k0 + 1) > kMaxCellsPerTriangle) {
                          for (std::uint32_t s = 0; s < cuts.size(); ++s)
                            if (cuts[s].seed().reach > 0.0) test(s);
                          continue;
                        }
                        for (std::int64_t i = i0; i <= i1; ++i)
                          for (std::int64_t j = j0; j <= j1; ++j)
                            for (std::int64_t k = k0; k <= k1; ++k) cells.for_each_in(i, j, k, test);
                      }
                    });
  std::vector<std::uint64_t> pairs;
  for (const auto& local : found) pairs.insert(pairs.end(), local.begin(), local.end());
  // Sorted, the pairs no longer depend on how the triangles were split between threads; a triangle
  // over several cells met its seeds once per cell.
  tbb::parallel_sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  std::vector<std::vector<std::uint32_t>> near(cuts.size());
  for (const std::uint64_t p : pairs) near[p >> 32].push_back(static_cast<std::uint32_t>(p & 0xFFFFFFFFu));
  return near;
}

std::uint64_t edge_key(std::int32_t a, std::int32_t b) {
  const auto lo = static_cast<std::uint64_t>(std::min(a, b)), hi = static_cast<std::uint64_t>(std::max(a, b));
  return (lo << 32) | hi;
}

// A closed loop of the cut in the plane's coordinates about the seed.
struct Loop {
  double area = 0.0;  // signed: positive counter-clockwise seen from the normal's tip
  double perimeter = 0.0;
  Eigen::Vector2d centroid = Eigen::Vector2d::Zero();
  Eigen::Matrix2d moments = Eigen::Matrix2d::Zero();  // of the area about the centroid, signed as `area`
  int winding = 0;                                    // winding number of the loop about the seed
};

Loop measure_loop(const std::vector<Eigen::Vector2d>& p) {
  Loop loop;
  double twice_area = 0.0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const Eigen::Vector2d& a = p[i];
    const Eigen::Vector2d& b = p[(i + 1) % p.size()];
    const double cross = a.x() * b.y() - a.y() * b.x();
    twice_area += cross;
    loop.centroid += (a + b) * cross;
    // Green's theorem per edge: the integrals of x^2, y^2 and xy over the area, times 12, 12 and 24.
    loop.moments(0, 0) += (a.x() * a.x() + a.x() * b.x() + b.x() * b.x()) * cross;
    loop.moments(1, 1) += (a.y() * a.y() + a.y() * b.y() + b.y() * b.y()) * cross;
    loop.moments(0, 1) += (a.x() * b.y() + 2.0 * a.x() * a.y() + 2.0 * b.x() * b.y() + b.x() * a.y()) * cross;
    loop.perimeter += (b - a).norm();
    // Sunday's winding number about the origin: upward crossings with the origin on the left count +1,
    // downward ones with it on the right -1.
    if (a.y() <= 0.0) {
      if (b.y() > 0.0 && cross > 0.0) ++loop.winding;
    } else if (b.y() <= 0.0 && cross < 0.0) {
      --loop.winding;
    }
  }
  loop.area = 0.5 * twice_area;
  loop.centroid =
      twice_area != 0.0 ? Eigen::Vector2d(loop.centroid / (3.0 * twice_area)) : Eigen::Vector2d::Zero();
  loop.moments(0, 0) /= 12.0;
  loop.moments(1, 1) /= 12.0;
  loop.moments(0, 1) /= 24.0;
  loop.moments -= loop.area * loop.centroid * loop.centroid.transpose();  // about the centroid
  loop.moments(1, 0) = loop.moments(0, 1);
  return loop;
}

// A loop bounds an opening where it runs counter-clockwise (see segment_of).
bool is_opening(const Loop& loop) {
  return loop.area > 0.0 && loop.perimeter > 0.0;
}

HoleRecord record_of(const Loop& loop, const Vec3& centre, const Vec3& normal) {
  HoleRecord r;
  r.centre = centre;
  r.normal = normal;
  r.diameter = std::sqrt(4.0 * loop.area / std::numbers::pi);
  r.circularity = 4.0 * std::numbers::pi * loop.area / (loop.perimeter * loop.perimeter);
  // The principal second moments of an ellipse's area are in the ratio (b / a)^2.
  const Eigen::Vector2d principal =
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(loop.moments).eigenvalues();
  r.axis_ratio = principal(1) > 0.0 ? std::sqrt(std::max(principal(0), 0.0) / principal(1)) : 0.0;
  return r;
}

// A triangle crossed by a cut (its vertices' sides `up`) gives the segment from the crossed edge where
// the walk around its border enters the side of its lone vertex to the one where it leaves (reversed
// for a lone vertex below): the solid then lies to the segment's right, and the loop around an opening
// runs counter-clockwise seen from the normal's tip. Both triangles at an edge agree on it, so the
// segments chain into loops.
struct Segment {
  std::array<std::int32_t, 2> from{}, to{};  // the edges' vertices
};

std::optional<Segment> segment_of(const std::array<std::int32_t, 3>& t, const std::array<bool, 3>& up) {
  if (up[0] == up[1] && up[1] == up[2]) return std::nullopt;
  const std::size_t lone = up[0] == up[1] ? 2 : (up[0] == up[2] ? 1 : 0);
  const std::int32_t prev = t[(lone + 2) % 3], self = t[lone], next = t[(lone + 1) % 3];
  if (up[lone]) return Segment{{prev, self}, {self, next}};
  return Segment{{self, next}, {prev, self}};
}

// The seed's hole: the smallest closed loop around the seed, if it bounds an opening (solid outside it).
std::optional<HoleRecord> cut_hole(const TriangleMesh& mesh, const CutSurface& cut,
                                   std::span<const std::uint32_t> triangles) {
  const auto vertex = [&](std::int32_t i) -> const Vec3& {
    return mesh.vertices[static_cast<std::size_t>(i)];
  };
  struct Keyed {
    std::uint64_t from = 0, to = 0;
    Segment segment;
    bool operator<(const Keyed& o) const { return from < o.from; }
  };
  std::vector<Keyed> segments;
  for (const std::uint32_t f : triangles) {
    const auto& t = mesh.triangles[f];
    if (const auto sg =
            segment_of(t, {cut.above(vertex(t[0])), cut.above(vertex(t[1])), cut.above(vertex(t[2]))}))
      segments.push_back({edge_key(sg->from[0], sg->from[1]), edge_key(sg->to[0], sg->to[1]), *sg});
  }
  std::sort(segments.begin(), segments.end());
  const auto starting_at = [&](std::uint64_t key) -> std::size_t {
    const auto it = std::lower_bound(segments.begin(), segments.end(), Keyed{key, 0, {}});
    return it != segments.end() && it->from == key ? static_cast<std::size_t>(it - segments.begin())
                                                   : segments.size();
  };
  // Where the cut crosses edge (a, b), in the plane's coordinates; the same from both of its triangles.
  const auto crossing = [&](std::int32_t a, std::int32_t b) {
    const Vec3& x = vertex(std::min(a, b));
    const Vec3& y = vertex(std::max(a, b));
    const double hx = cut.height(x), hy = cut.height(y);
    return cut.plane(x + (hx / (hx - hy)) * (y - x));
  };
  std::optional<Loop> best;
  std::vector<char> used(segments.size(), 0);
  std::vector<Eigen::Vector2d> points;
  for (std::size_t first = 0; first < segments.size(); ++first) {
    if (used[first]) continue;
    points.clear();
    bool closed = false;
    for (std::size_t s = first;;) {
      used[s] = 1;
      points.push_back(crossing(segments[s].segment.from[0], segments[s].segment.from[1]));
      const std::size_t next = starting_at(segments[s].to);
      if (next == first) closed = true;
      if (next == segments.size() || used[next]) break;  // an open chain, cut off by the reach
      s = next;
    }
    if (!closed || points.size() < 3) continue;
    const Loop loop = measure_loop(points);
    if (loop.winding != 0 && (!best || std::abs(loop.area) < std::abs(best->area))) best = loop;
  }
  // Clockwise: the seed lies in solid, enclosed by an outer edge of the cut, not in an opening.
  if (!best || !is_opening(*best)) return std::nullopt;
  return record_of(*best, cut.lift(best->centroid), cut.seed().normal);
}

// The triangles around each vertex, for walking from a triangle to its neighbour across an edge (every
// triangle at a vertex, unlike geometry's vertex_triangles, which leaves out repeated indices).
class TriangleNeighbours {
 public:
  explicit TriangleNeighbours(const TriangleMesh& mesh) : first_(mesh.vertices.size() + 1, 0) {
    for (const auto& t : mesh.triangles)
      for (const std::int32_t v : t) ++first_[static_cast<std::size_t>(v) + 1];
    for (std::size_t v = 1; v < first_.size(); ++v) first_[v] += first_[v - 1];
    triangles_.resize(static_cast<std::size_t>(first_.back()));
    std::vector<std::int64_t> at(first_.begin(), first_.end() - 1);
    for (std::size_t f = 0; f < mesh.triangles.size(); ++f)
      for (const std::int32_t v : mesh.triangles[f])
        triangles_[static_cast<std::size_t>(at[static_cast<std::size_t>(v)]++)] =
            static_cast<std::uint32_t>(f);
  }
  // The triangle other than f with vertices a and b (the first, where the edge is not manifold).
  std::optional<std::uint32_t> across(const TriangleMesh& mesh, std::uint32_t f, std::int32_t a,
                                      std::int32_t b) const {
    const auto begin = static_cast<std::size_t>(first_[static_cast<std::size_t>(a)]);
    const auto end = static_cast<std::size_t>(first_[static_cast<std::size_t>(a) + 1]);
    for (std::size_t i = begin; i < end; ++i) {
      const std::uint32_t g = triangles_[i];
      const auto& t = mesh.triangles[g];
      if (g != f && (t[0] == b || t[1] == b || t[2] == b)) return g;
    }
    return std::nullopt;
  }

 private:
  std::vector<std::int64_t> first_;
  std::vector<std::uint32_t> triangles_;
};

// Where the model cut finds no loop (a wall curving away within the hole's radius, a crease beside
// it), the loop where the hole's wall crosses the wall's middle itself, traced across the mesh from
// triangle to triangle: it closes on any closed mesh. Starts from the model cut's crossings nearest the
// seed, a few of them, and keeps the first loop around the seed that bounds an opening.
std::optional<HoleRecord> trace_hole(const TriangleMesh& mesh, const TriangleNeighbours& around,
                                     const CutSurface& cut, const MidWall& mid_wall,
                                     std::span<const std::uint32_t> triangles) {
  const HoleSeed& seed = cut.seed();
  const auto vertex = [&](std::int32_t i) -> const Vec3& {
    return mesh.vertices[static_cast<std::size_t>(i)];
  };
  std::unordered_map<std::int32_t, double> heights;
  const auto height = [&](std::int32_t v) {
    const auto [it, fresh] = heights.try_emplace(v, 0.0);
    if (fresh) it->second = mid_wall.height(vertex(v), seed.normal).value_or(0.0);
    return it->second;
  };
  const auto segment = [&](std::uint32_t f) {
    const auto& t = mesh.triangles[f];
    return segment_of(t, {height(t[0]) >= 0.0, height(t[1]) >= 0.0, height(t[2]) >= 0.0});
  };
  const auto crossing = [&](const std::array<std::int32_t, 2>& e) {
    const std::int32_t a = std::min(e[0], e[1]), b = std::max(e[0], e[1]);
    const double ha = height(a), hb = height(b);
    return Vec3(vertex(a) + (ha / (ha - hb)) * (vertex(b) - vertex(a)));
  };
  std::vector<std::pair<double, std::uint32_t>> starts;
  for (const std::uint32_t f : triangles) {
    const auto& t = mesh.triangles[f];
    starts.push_back({(vertex(t[0]) + vertex(t[1]) + vertex(t[2]) - 3.0 * seed.point).norm(), f});
  }
  std::sort(starts.begin(), starts.end());
  std::unordered_set<std::uint32_t> visited;
  std::vector<Eigen::Vector2d> points;
  int tries = 0;
  for (const auto& [distance, first] : starts) {
    if (tries == kTraceStarts) break;
    std::optional<Segment> s = segment(first);
    if (!s || visited.contains(first)) continue;
    ++tries;
    points.clear();
    bool closed = false;
    for (std::uint32_t f = first;;) {
      visited.insert(f);
      const Vec3 x = crossing(s->from);
      if ((x - seed.point).norm() > seed.reach) break;  // not this hole's loop
      points.push_back(cut.plane(x));
      const std::optional<std::uint32_t> next = around.across(mesh, f, s->to[0], s->to[1]);
      if (!next || (*next != first && visited.contains(*next))) break;
      if (*next == first) {
        closed = true;
        break;
      }
      f = *next;
      s = segment(f);
      if (!s) break;
    }
    if (!closed || points.size() < 3) continue;
    const Loop loop = measure_loop(points);
    if (loop.winding == 0 || !is_opening(loop)) continue;
    const Vec3 centre = cut.lift(loop.centroid);  // the model may be off here: take the middle's point
    return record_of(loop, mid_wall.point(centre, seed.normal).value_or(centre), seed.normal);
  }
  return std::nullopt;
}

}  // namespace

std::vector<std::optional<HoleRecord>> cut_holes(const TriangleMesh& mesh, std::span<const HoleSeed> seeds,
                                                 const MidWall* mid_wall) {
  if (seeds.empty()) return {};  // no pass over the triangles
  std::vector<CutSurface> cuts;
  cuts.reserve(seeds.size());
  for (const HoleSeed& seed : seeds) cuts.emplace_back(seed, nullptr);
  if (mid_wall)
    tbb::parallel_for(std::size_t{0}, seeds.size(),
                      [&](std::size_t s) { cuts[s] = CutSurface(seeds[s], mid_wall); });
  const std::vector<std::vector<std::uint32_t>> near = crossing_triangles(mesh, cuts);
  std::vector<std::optional<HoleRecord>> cut(seeds.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, seeds.size(), 8),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      for (std::size_t s = range.begin(); s != range.end(); ++s)
                        if (seeds[s].reach > 0.0) cut[s] = cut_hole(mesh, cuts[s], near[s]);
                    });
  std::vector<std::size_t> missed;
  for (std::size_t s = 0; s < seeds.size(); ++s)
    if (!cut[s] && seeds[s].reach > 0.0 && !near[s].empty()) missed.push_back(s);
  if (!mid_wall || missed.empty()) return cut;
  const TriangleNeighbours around(mesh);
  tbb::parallel_for(std::size_t{0}, missed.size(), [&](std::size_t i) {
    const std::size_t s = missed[i];
    cut[s] = trace_hole(mesh, around, cuts[s], *mid_wall, near[s]);
  });
  return cut;
}

}  // namespace poreshell
