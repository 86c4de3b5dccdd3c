#include "geometry/point_tree.hpp"

// Hand-written although Debian has nanoflann (libnanoflann-dev): the splats need closest() with a
// per-item distance (a disc, not a point), which nanoflann's k-d tree does not offer. For plain points
// nanoflann is faster: bench/point_tree_vs_nanoflann.cpp on the bunny's 35,947 points, 200k queries
// near them, one thread, loaded 2-core VM: build 0.027 s vs 0.012 s, nearest 1.74 s vs 0.52 s (3.4x),
// 9 nearest 27.3 s vs 1.09 s (25x), 10 nearest 32.9 s vs 1.13 s (29x); on 2.7 M random points build
// 1.5x, nearest 2.9x, k nearest 92-99x slower (docs/benchmarks.md, "PointTree against nanoflann"). k_nearest
// visits children in a fixed order, not nearer first, so its k-th distance stays loose: fixing that (or
// nanoflann for nearest / k_nearest) is a separate decision.

#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <queue>
#include <stdexcept>

#include "core/error.hpp"

namespace poreshell {
namespace {

constexpr std::int32_t kLeafSize = 8;

}  // namespace

// An item during the build, its point and radius beside its index: the median splits then read one run
// of memory instead of a random point per comparison.
struct PointTree::BuildSlot {
  Vec3 point;
  double radius;
  std::int32_t index;
};

namespace {

std::int32_t leaf_count(std::int32_t items) {
  return items <= kLeafSize ? 1 : leaf_count(items / 2) + leaf_count(items - items / 2);
}

// Above this many items a node's two subtrees are built in parallel.
constexpr std::int32_t kParallelItems = 1 << 16;

}  // namespace

PointTree::PointTree(const std::vector<Vec3>& points, const std::vector<double>& radii) : points_(points) {
  if (points_.empty()) throw InputError("a point tree needs at least one point");
  if (points_.size() > static_cast<std::size_t>(INT32_MAX / 2))
    throw InputError("too many points (over 2^30)");
  if (!radii.empty() && radii.size() != points_.size())
    throw std::invalid_argument("a point tree needs one radius per point, or none");
  const auto n = static_cast<std::int32_t>(points_.size());
  std::vector<BuildSlot> slots(points_.size());
  for (std::int32_t i = 0; i < n; ++i) {
    const auto u = static_cast<std::size_t>(i);
    slots[u] = {points_[u], radii.empty() ? 0.0 : radii[u], i};  // the radii live on in the nodes' bounds
  }
  // A full binary tree: 2 leaves - 1 nodes, numbered as a depth-first build would number them.
  nodes_.resize(2 * static_cast<std::size_t>(leaf_count(n)) - 1);
  build(slots, 0, 0, n, 1);
  order_.resize(points_.size());
  leaf_points_.resize(points_.size());
  for (std::size_t s = 0; s < slots.size(); ++s) {
    order_[s] = slots[s].index;
    leaf_points_[s] = slots[s].point;
  }
}

// Node `node` over slots [begin, end); its children are nodes first_free and first_free + 1, and their
// subtrees take the numbers after those, the left subtree's first.
void PointTree::build(std::vector<BuildSlot>& slots, std::int32_t node, std::int32_t begin, std::int32_t end,
                      std::int32_t first_free) {
  Node n;
  n.lo = n.hi = slots[static_cast<std::size_t>(begin)].point;
  for (std::int32_t s = begin; s < end; ++s) {
    const BuildSlot& slot = slots[static_cast<std::size_t>(s)];
    n.lo = n.lo.cwiseMin(slot.point);
    n.hi = n.hi.cwiseMax(slot.point);
    n.radius = std::max(n.radius, slot.radius);
  }
  if (end - begin <= kLeafSize) {
    n.first = begin;
    n.count = end - begin;
    nodes_[static_cast<std::size_t>(node)] = n;
    return;
  }
  int axis = 0;
  (n.hi - n.lo).maxCoeff(&axis);
  const std::int32_t mid = begin + (end - begin) / 2;
  // Ties broken by index so that the tree, and hence every answer, is deterministic.
  std::nth_element(slots.begin() + begin, slots.begin() + mid, slots.begin() + end,
                   [axis](const BuildSlot& a, const BuildSlot& b) {
                     const double pa = a.point[axis], pb = b.point[axis];
                     return pa < pb || (pa == pb && a.index < b.index);
                   });
  n.first = first_free;
  n.count = 0;
  nodes_[static_cast<std::size_t>(node)] = n;
  const std::int32_t left_nodes = 2 * leaf_count(mid - begin) - 1;
  const auto left = [&] { build(slots, first_free, begin, mid, first_free + 2); };
  const auto right = [&] { build(slots, first_free + 1, mid, end, first_free + 1 + left_nodes); };
  if (end - begin >= kParallelItems) {
    tbb::parallel_invoke(left, right);
  } else {
    left();
    right();
  }
}

// The closest-slot search without radii, in squared distances, each node's bound computed once (kept on
// the stack with it): the multigrid's coarse bands make millions of these queries.
std::pair<std::size_t, double> PointTree::nearest(const Vec3& x) const {
  const auto squared_bound = [&](const Node& n) {
    return (n.lo - x).cwiseMax(x - n.hi).cwiseMax(0.0).squaredNorm();
  };
  std::int32_t best = -1;
  double best_d2 = std::numeric_limits<double>::infinity();
  std::pair<std::int32_t, double> stack[128];  // depth <= 31 for 2^31 points, two entries a level
  int top = 0;
  stack[top++] = {0, squared_bound(nodes_[0])};
  while (top > 0) {
    const auto [index, node_d2] = stack[--top];
    if (node_d2 > best_d2) continue;
    const Node& n = nodes_[static_cast<std::size_t>(index)];
    if (n.count > 0) {
      for (std::int32_t s = n.first; s < n.first + n.count; ++s) {
        const double d2 = (leaf_points_[static_cast<std::size_t>(s)] - x).squaredNorm();
        if (d2 < best_d2 || (d2 == best_d2 && item(s) < item(best))) {
          best_d2 = d2;
          best = s;
        }
      }
      continue;
    }
    push_children(n, squared_bound, stack, top);
  }
  return {item(best), std::sqrt(best_d2)};
}

// As nearest(): the nearer child first, so that the k-th distance tightens early and prunes the rest
// (visiting children in a fixed order made this 25-99 times slower than nanoflann; docs/benchmarks.md).
// The result does not depend on the order: the k least (distance, index) pairs.
std::vector<std::size_t> PointTree::k_nearest(const Vec3& x, std::size_t k) const {
  k = std::min(k, points_.size());
  if (k == 0) return {};
  // Max-heap of the best k (distance, index); its top is the current k-th distance.
  std::priority_queue<std::pair<double, std::size_t>> best;
  const auto kth = [&] {
    return best.size() < k ? std::numeric_limits<double>::infinity() : best.top().first;
  };
  std::pair<std::int32_t, double> stack[128];  // depth <= 31 for 2^31 points, two entries a level
  int top = 0;
  stack[top++] = {0, bound(nodes_[0], x)};
  while (top > 0) {
    const auto [index, node_bound] = stack[--top];
    if (node_bound > kth()) continue;
    const Node& n = nodes_[static_cast<std::size_t>(index)];
    if (n.count == 0) {
      push_children(
          n, [&](const Node& child) { return bound(child, x); }, stack, top);
      continue;
    }
    for (std::int32_t s = n.first; s < n.first + n.count; ++s) {
      const std::pair<double, std::size_t> candidate{(leaf_points_[static_cast<std::size_t>(s)] - x).norm(),
                                                     item(s)};
      if (best.size() < k) {
        best.push(candidate);
      } else if (candidate < best.top()) {
        best.pop();
        best.push(candidate);
      }
    }
  }
  std::vector<std::size_t> out(best.size());
  for (std::size_t j = out.size(); j-- > 0; best.pop()) out[j] = best.top().second;
  return out;
}

}  // namespace poreshell
