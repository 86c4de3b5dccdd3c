#include "geometry/mesh_surface.hpp"

// Bounding-volume hierarchy over triangles, chosen over a sparse distance grid because the band
// builder asks for distances anywhere in the domain (block centres far from the surface too): a BVH
// is exact everywhere and needs O(triangles) memory. Median splits keep it balanced, so the query
// stack has a fixed bound. Queries only read the tree and are safe to run from many threads. Embree's
// point query with the same triangle test is 1.17x slower on the bunny's near field
// (bench/mesh_distance_vs_embree.cpp, docs/benchmarks.md).

#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>

#include <Eigen/Geometry>  // cross()
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "core/error.hpp"

namespace poreshell {
namespace {

constexpr std::int32_t kLeafSize = 4;
constexpr int kMaxDepth = 64;  // median splits below kSahDepth: depth <= kSahDepth + log2(2^31) + 1
constexpr int kSahDepth = 30;  // surface-area splits down to here, then medians
// Halves of at least this many triangles are built at once. The constructor on the bunny's 1.5 M-triangle
// shell: 0.89-1.02 s building on one thread, 0.66-0.80 s on two (docs/benchmarks.md "The reduction's
// set-up").
constexpr std::int32_t kParallelBuild = 20'000;

Vec3 closest_point_on_segment(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 ab = b - a;
  const double len2 = ab.squaredNorm();
  if (!(len2 > 0.0)) return a;
  return a + std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) * ab;
}

// Nearest of the three edges: exact for a zero-area triangle, which is the union of its edges.
Vec3 closest_point_on_edges(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  Vec3 best = closest_point_on_segment(p, a, b);
  for (const Vec3& q : {closest_point_on_segment(p, b, c), closest_point_on_segment(p, c, a)})
    if ((q - p).squaredNorm() < (best - p).squaredNorm()) best = q;
  return best;
}

// Region-based closest point (Voronoi regions of vertices, edges, face) for a triangle with area.
Vec3 closest_point_by_regions(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const Vec3 bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + (d1 / (d1 - d3)) * ab;
  const Vec3 cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + (d2 / (d2 - d6)) * ac;
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0) return b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b);
  // Exact arithmetic only gets here with va, vb, vc > 0. If round-off broke that (slivers), the
  // projection is next to an edge, and the edges give the answer.
  if (!(va >= 0 && vb >= 0 && vc >= 0 && va + vb + vc > 0)) return closest_point_on_edges(p, a, b, c);
  const double inv = 1.0 / (va + vb + vc);
  return a + (vb * inv) * ab + (vc * inv) * ac;
}

double box_distance2(const Vec3& p, const Vec3& lo, const Vec3& hi) {
  double d2 = 0.0;
  for (int axis = 0; axis < 3; ++axis) {
    const double e = std::max({lo[axis] - p[axis], 0.0, p[axis] - hi[axis]});
    d2 += e * e;
  }
  return d2;
}

}  // namespace

TriangleShape classify_triangle(const Vec3& a, const Vec3& b, const Vec3& c) {
  const TriangleSize size = triangle_size(a, b, c);
  if (size.zero_area()) return TriangleShape::degenerate;
  return size.twice_area > 1e-4 * size.longest2 ? TriangleShape::regular : TriangleShape::sliver;
}

Vec3 closest_point_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c,
                               TriangleShape shape) {
  // Zero area: the region tests divide by zero, and the edges are the whole triangle.
  if (shape == TriangleShape::degenerate) return closest_point_on_edges(p, a, b, c);
  const Vec3 q = closest_point_by_regions(p, a, b, c);
  if (shape == TriangleShape::regular) return q;
  // Slivers: the region tests cancel digits and may pick a neighbouring region. Every candidate
  // lies on the triangle, so the nearest of them is the better answer.
  const Vec3 e = closest_point_on_edges(p, a, b, c);
  return (e - p).squaredNorm() < (q - p).squaredNorm() ? e : q;
}

Vec3 closest_point_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  return closest_point_on_triangle(p, a, b, c, classify_triangle(a, b, c));
}

MeshSurface::MeshSurface(const TriangleMesh& mesh) {
  // Checked on the input count, so that input_index_ holds every input index.
  if (mesh.triangles.size() > static_cast<std::size_t>(INT32_MAX / 2))
    throw InputError("the mesh has too many triangles (over 2^30): decimate it");
  std::vector<Tri> tris;
  std::vector<std::int32_t> input_index;
  tris.reserve(mesh.triangles.size());
  input_index.reserve(mesh.triangles.size());
  for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
    const auto& t = mesh.triangles[i];
    if (has_repeated_vertex(t)) continue;
    Tri tri{mesh.vertices.at(t[0]), mesh.vertices.at(t[1]), mesh.vertices.at(t[2])};
    if (!tri.a.allFinite() || !tri.b.allFinite() || !tri.c.allFinite())
      throw InputError("the mesh has a vertex with a NaN or infinite coordinate: repair the mesh");
    tri.shape = classify_triangle(tri.a, tri.b, tri.c);
    tri.centre = (tri.a + tri.b + tri.c) / 3.0;
    tri.radius = std::sqrt(std::max({(tri.a - tri.centre).squaredNorm(), (tri.b - tri.centre).squaredNorm(),
                                     (tri.c - tri.centre).squaredNorm()}));
    tris.push_back(tri);
    input_index.push_back(static_cast<std::int32_t>(i));
  }
  if (tris.empty()) throw InputError("the mesh has no triangles: it cannot define a surface");

  std::vector<Vec3> centroids(tris.size());
  for (std::size_t i = 0; i < tris.size(); ++i) centroids[i] = (tris[i].a + tris[i].b + tris[i].c) / 3.0;
  std::vector<std::int32_t> order(tris.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = static_cast<std::int32_t>(i);
  nodes_.reserve(4 * tris.size() / kLeafSize + 1);
  nodes_.push_back({});
  build(nodes_, 0, order, tris, centroids, 0, static_cast<std::int32_t>(tris.size()), 0);
  tris_.resize(tris.size());
  input_index_.resize(tris.size());
  tbb::parallel_for(std::size_t{0}, order.size(), [&](std::size_t k) {
    tris_[k] = tris[static_cast<std::size_t>(order[k])];
    input_index_[k] = input_index[static_cast<std::size_t>(order[k])];
  });
}

// Binned surface-area split of order[begin, end) along `axis` (16 bins over the centroids' extent
// [clo, chi]): boxes that hug the surface's pieces, so a search opens fewer of them than after median
// splits (docs/benchmarks.md "Mesh distance against Embree's point query"). Partitions order and returns
// the split, or -1 where no bin boundary separates the triangles.
std::int32_t MeshSurface::split_by_area(std::vector<std::int32_t>& order, const std::vector<Tri>& tris,
                                        const std::vector<Vec3>& centroids, std::int32_t begin,
                                        std::int32_t end, int axis, const Vec3& clo, const Vec3& chi) {
  constexpr int kBins = 16;
  const double extent = chi[axis] - clo[axis];
  if (!(extent > 0.0)) return -1;
  struct Bin {
    Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
    std::int32_t count = 0;
  };
  std::array<Bin, kBins> bins;
  const auto bin_of = [&](std::int32_t t) {
    return std::min(kBins - 1, static_cast<int>(kBins * (centroids[t][axis] - clo[axis]) / extent));
  };
  for (std::int32_t i = begin; i < end; ++i) {
    const Tri& t = tris[order[i]];
    Bin& b = bins[static_cast<std::size_t>(bin_of(order[i]))];
    b.lo = b.lo.cwiseMin(t.a).cwiseMin(t.b).cwiseMin(t.c);
    b.hi = b.hi.cwiseMax(t.a).cwiseMax(t.b).cwiseMax(t.c);
    ++b.count;
  }
  const auto area = [](const Vec3& l, const Vec3& h) {
    if (!(l.x() <= h.x())) return 0.0;
    const Vec3 e = h - l;
    return e.x() * e.y() + e.y() * e.z() + e.z() * e.x();
  };
  // Cost of a split after bin b: area times count of each side.
  std::array<double, kBins> right_cost{};
  Bin right;
  for (int b = kBins - 1; b > 0; --b) {
    const Bin& bin = bins[static_cast<std::size_t>(b)];
    right = {right.lo.cwiseMin(bin.lo), right.hi.cwiseMax(bin.hi), right.count + bin.count};
    right_cost[static_cast<std::size_t>(b)] = area(right.lo, right.hi) * right.count;
  }
  Bin left;
  double best = std::numeric_limits<double>::infinity();
  int split = -1;
  for (int b = 0; b < kBins - 1; ++b) {
    const Bin& bin = bins[static_cast<std::size_t>(b)];
    left = {left.lo.cwiseMin(bin.lo), left.hi.cwiseMax(bin.hi), left.count + bin.count};
    if (left.count == 0 || left.count == end - begin) continue;
    const double cost = area(left.lo, left.hi) * left.count + right_cost[static_cast<std::size_t>(b + 1)];
    if (cost < best) {
      best = cost;
      split = b;
    }
  }
  if (split < 0) return -1;
  const auto middle = std::stable_partition(order.begin() + begin, order.begin() + end,
                                            [&](std::int32_t t) { return bin_of(t) <= split; });
  return static_cast<std::int32_t>(middle - order.begin());
}

void MeshSurface::build(std::vector<Node>& nodes, std::int32_t node, std::vector<std::int32_t>& order,
                        const std::vector<Tri>& tris, const std::vector<Vec3>& centroids, std::int32_t begin,
                        std::int32_t end, int depth) {
  Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  Vec3 clo = lo, chi = hi;
  for (std::int32_t i = begin; i < end; ++i) {
    const Tri& t = tris[order[i]];
    lo = lo.cwiseMin(t.a).cwiseMin(t.b).cwiseMin(t.c);
    hi = hi.cwiseMax(t.a).cwiseMax(t.b).cwiseMax(t.c);
    clo = clo.cwiseMin(centroids[order[i]]);
    chi = chi.cwiseMax(centroids[order[i]]);
  }
  nodes[node] = {lo, hi, begin, end - begin};
  if (end - begin <= kLeafSize) return;

  int axis = 0;
  (chi - clo).maxCoeff(&axis);
  std::int32_t mid =
      depth < kSahDepth ? split_by_area(order, tris, centroids, begin, end, axis, clo, chi) : -1;
  if (mid < 0) {
    mid = begin + (end - begin) / 2;
    std::nth_element(order.begin() + begin, order.begin() + mid, order.begin() + end,
                     [&](std::int32_t x, std::int32_t y) { return centroids[x][axis] < centroids[y][axis]; });
  }
  const auto left = static_cast<std::int32_t>(nodes.size());
  nodes.push_back({});
  nodes.push_back({});
  nodes[node].first = left;
  nodes[node].count = 0;
  if (end - begin < 2 * kParallelBuild) {
    build(nodes, left, order, tris, centroids, begin, mid, depth + 1);
    build(nodes, left + 1, order, tris, centroids, mid, end, depth + 1);
    return;
  }
  // The halves at once, on their own parts of `order`: the right one into a vector of its own, its
  // root first, spliced after the left one's nodes where one thread would have put them (the same
  // tree on any thread count).
  std::vector<Node> right(1);
  tbb::parallel_invoke([&] { build(nodes, left, order, tris, centroids, begin, mid, depth + 1); },
                       [&] { build(right, 0, order, tris, centroids, mid, end, depth + 1); });
  const auto offset = static_cast<std::int32_t>(nodes.size()) - 1;  // right[k] goes to offset + k, k >= 1
  for (Node& n : right)
    if (n.count == 0) n.first += offset;
  nodes[static_cast<std::size_t>(left) + 1] = right.front();
  nodes.insert(nodes.end(), right.begin() + 1, right.end());
}

double MeshSurface::nearest(const Vec3& p, Vec3& closest, std::int32_t& index, double bound2) const {
  struct Pending {
    std::int32_t node;
    double d2;  // lower bound: squared distance to its box
  };
  std::array<Pending, kMaxDepth> stack;
  int top = 0;
  double best = bound2;
  std::int32_t node = 0;
  for (;;) {
    const Node& n = nodes_[node];
    if (n.count > 0) {
      for (std::int32_t i = n.first; i < n.first + n.count; ++i) {
        const Tri& t = tris_[i];
        const double reach = std::sqrt(best) + t.radius;
        if ((p - t.centre).squaredNorm() > reach * reach) continue;
        const Vec3 q = closest_point_on_triangle(p, t.a, t.b, t.c, t.shape);
        const double d2 = (q - p).squaredNorm();
        if (d2 < best) {
          best = d2;
          closest = q;
          index = i;
        }
      }
    } else {
      // Nearer child first: it usually finds a small bound that prunes the other.
      std::int32_t near = n.first, far = n.first + 1;
      double dnear = box_distance2(p, nodes_[near].lo, nodes_[near].hi);
      double dfar = box_distance2(p, nodes_[far].lo, nodes_[far].hi);
      if (dfar < dnear) {
        std::swap(near, far);
        std::swap(dnear, dfar);
      }
      if (dnear < best) {
        if (dfar < best) stack[top++] = {far, dfar};
        node = near;
        continue;
      }
    }
    while (top > 0 && stack[top - 1].d2 >= best) --top;
    if (top == 0) break;
    node = stack[--top].node;
  }
  return best;
}

double MeshSurface::distance(const Vec3& p) const {
  return distance_and_closest_point(p).distance;
}

// The band scan's block tests ask mostly about points beyond their bound (blocks far from the surface),
// where the search leaves after a few boxes instead of finding the nearest triangle.
double MeshSurface::distance_up_to(const Vec3& p, double bound) const {
  Vec3 closest;
  std::int32_t index = 0;
  const double searched = bound * (1.0 + 1e-12) + std::numeric_limits<double>::min();
  const double d2 = nearest(p, closest, index, searched * searched);
  return d2 < searched * searched ? std::sqrt(d2) : std::numeric_limits<double>::infinity();
}

std::optional<Vec3> MeshSurface::closest_point(const Vec3& p) const {
  return distance_and_closest_point(p).closest_point;
}

SurfaceQuery MeshSurface::distance_and_closest_point(const Vec3& p) const {
  Vec3 closest;
  std::int32_t index = 0;
  const double d2 = nearest(p, closest, index);
  return {std::sqrt(d2), closest};
}

// The search starts bounded by the hint's distance: boxes beyond it are never opened, where an
// unbounded search first descends into whichever box holds p and only then prunes.
SurfaceQuery MeshSurface::distance_and_closest_point_near(const Vec3& p, const Vec3& on_surface) const {
  Vec3 closest;
  std::int32_t index = -1;
  const double bound = (p - on_surface).norm() * (1.0 + 1e-9) + std::numeric_limits<double>::min();
  const double d2 = nearest(p, closest, index, bound * bound);
  if (index < 0) return distance_and_closest_point(p);  // the hint was not on the surface
  return {std::sqrt(d2), closest};
}

MeshSurface::NearestTriangle MeshSurface::nearest_triangle(const Vec3& p) const {
  NearestTriangle out;
  std::int32_t index = 0;
  nearest(p, out.point, index);
  out.triangle = static_cast<std::size_t>(input_index_[static_cast<std::size_t>(index)]);
  return out;
}

std::optional<MeshSurface::NearestTriangle> MeshSurface::nearest_triangle_within(const Vec3& p,
                                                                                 double reach) const {
  NearestTriangle out;
  std::int32_t index = -1;
  nearest(p, out.point, index, reach * reach);
  if (index < 0) return std::nullopt;
  out.triangle = static_cast<std::size_t>(input_index_[static_cast<std::size_t>(index)]);
  return out;
}

Box MeshSurface::bounds() const {
  return {nodes_[0].lo, nodes_[0].hi};
}

}  // namespace poreshell
