#pragma once
// Union-find on one thread (geometry/mesh.cpp has a concurrent one for the topology pass). Each set's
// root is its lowest element, so the roots, and whatever is numbered by them, do not depend on the
// order of the unions.

#include <algorithm>
#include <cstdint>
#include <numeric>
#include <vector>

namespace poreshell {

class DisjointSets {
 public:
  explicit DisjointSets(std::size_t n = 0) { reset(n); }

  // n singletons 0 .. n - 1.
  void reset(std::size_t n) {
    parent_.resize(n);
    std::iota(parent_.begin(), parent_.end(), 0);
  }
  std::int32_t find(std::int32_t x) {
    while (parent_[static_cast<std::size_t>(x)] != x)  // path halving
      x = parent_[static_cast<std::size_t>(x)] =
          parent_[static_cast<std::size_t>(parent_[static_cast<std::size_t>(x)])];
    return x;
  }
  void unite(std::int32_t a, std::int32_t b) {
    a = find(a);
    b = find(b);
    if (a != b) parent_[static_cast<std::size_t>(std::max(a, b))] = std::min(a, b);
  }

 private:
  std::vector<std::int32_t> parent_;
};

}  // namespace poreshell
