#pragma once
// Bounding-volume tree over points (with optional radii): nearest, k nearest and custom closest-item
// queries. Used by the point-cloud surfaces and by the multigrid's coarse bands.

#include <cstdint>
#include <limits>
#include <utility>
#include <vector>

#include "core/types.hpp"

namespace poreshell {

// Bounding-volume tree over points, each with a radius (0 for plain points): the bound for a node is
// the distance to its box of centres minus its largest radius. Deterministic (median splits).
class PointTree {
 public:
  explicit PointTree(const std::vector<Vec3>& points, const std::vector<double>& radii = {});

  std::size_t size() const { return order_.size(); }
  const Vec3& point(std::size_t i) const { return points_[i]; }

  // Index and distance of the nearest point (ties: the lower index).
  std::pair<std::size_t, double> nearest(const Vec3& x) const;
  // The k nearest points, nearest first (ties: the lower index).
  std::vector<std::size_t> k_nearest(const Vec3& x, std::size_t k) const;

  // Smallest item_distance(i) over all items, pruning nodes whose bound exceeds the best so far.
  // item_distance(i) must be >= |x - point(i)| - radius(i).
  template <class F>
  std::pair<std::size_t, double> closest(const Vec3& x, F&& item_distance) const;

 private:
  struct Node {
    Vec3 lo = Vec3::Zero(), hi = Vec3::Zero();
    double radius = 0.0;     // largest item radius below this node
    std::int32_t first = 0;  // leaf: first slot in order_; inner: left child (right child is first + 1)
    std::int32_t count = 0;  // leaf: number of items; inner: 0
  };
  struct BuildSlot;
  void build(std::vector<BuildSlot>& slots, std::int32_t node, std::int32_t begin, std::int32_t end,
             std::int32_t first_free);
  // The item in leaf slot s (-1: none, ordered after every item).
  std::size_t item(std::int32_t s) const {
    return s < 0 ? std::numeric_limits<std::size_t>::max()
                 : static_cast<std::size_t>(order_[static_cast<std::size_t>(s)]);
  }
  template <class F>
  std::pair<std::int32_t, double> closest_slot(const Vec3& x, F&& slot_distance) const;
  // Pushes an inner node's children with their bounds, the nearer last so that it is popped first.
  template <class Bound>
  void push_children(const Node& n, const Bound& bound_of, std::pair<std::int32_t, double>* stack,
                     int& top) const {
    const double bl = bound_of(nodes_[static_cast<std::size_t>(n.first)]);
    const double br = bound_of(nodes_[static_cast<std::size_t>(n.first + 1)]);
    const bool left_nearer = bl < br;
    stack[top++] = left_nearer ? std::pair{n.first + 1, br} : std::pair{n.first, bl};
    stack[top++] = left_nearer ? std::pair{n.first, bl} : std::pair{n.first + 1, br};
  }
  double bound(const Node& n, const Vec3& x) const {
    const Vec3 d = (n.lo - x).cwiseMax(x - n.hi).cwiseMax(0.0);
    return d.norm() - n.radius;
  }

  std::vector<Vec3> points_;
  std::vector<std::int32_t> order_;  // item indices in leaf order
  std::vector<Vec3> leaf_points_;    // points in leaf order: a leaf's points in one run of memory
  std::vector<Node> nodes_;
};

// ---- template implementation ----

template <class F>
std::pair<std::size_t, double> PointTree::closest(const Vec3& x, F&& item_distance) const {
  const auto [slot, d] = closest_slot(x, [&](std::int32_t s) { return item_distance(item(s)); });
  return {item(slot), d};
}

template <class F>
std::pair<std::int32_t, double> PointTree::closest_slot(const Vec3& x, F&& slot_distance) const {
  std::int32_t best = -1;
  double best_d = std::numeric_limits<double>::infinity();
  std::int32_t stack[128];  // depth <= 31 for 2^31 points, two entries a level
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& n = nodes_[static_cast<std::size_t>(stack[--top])];
    if (bound(n, x) > best_d) continue;
    if (n.count > 0) {
      for (std::int32_t s = n.first; s < n.first + n.count; ++s) {
        const double d = slot_distance(s);
        if (d < best_d || (d == best_d && item(s) < item(best))) {
          best_d = d;
          best = s;
        }
      }
      continue;
    }
    // Nearer child last, so it is popped first.
    const double bl = bound(nodes_[static_cast<std::size_t>(n.first)], x);
    const double br = bound(nodes_[static_cast<std::size_t>(n.first + 1)], x);
    if (bl < br) {
      stack[top++] = n.first + 1;
      stack[top++] = n.first;
    } else {
      stack[top++] = n.first;
      stack[top++] = n.first + 1;
    }
  }
  return {best, best_d};
}

}  // namespace poreshell
