#include "core/grid.hpp"

#include <algorithm>
#include <cmath>

#include "core/error.hpp"

namespace poreshell {

Grid::Grid(const Vec3& origin, double h, std::array<int, 3> dims) : origin_(origin), h_(h), dims_(dims) {
  if (!(h > 0.0) || !std::isfinite(h)) throw InputError("grid spacing h must be a positive finite number");
  for (int n : dims)
    if (n < 3) throw InputError("every grid dimension must have at least 3 points");
}

Grid Grid::fitted(const Box& box, int points_longest) {
  if (points_longest < 3)
    throw OptionError("resolution", "`resolution` must be at least 3 points along the longest side");
  const Vec3 size = box.max - box.min;
  const double longest = size.maxCoeff();
  if (!(longest > 0.0)) throw InputError("the domain has zero size");
  const double h = longest / (points_longest - 1);
  std::array<int, 3> dims{};
  for (int a = 0; a < 3; ++a) dims[a] = std::max(3, static_cast<int>(std::lround(size[a] / h)) + 1);
  return Grid(box.min, h, dims);
}

Coord Grid::coord(std::int64_t key) const {
  const std::int64_t nx = dims_[0], ny = dims_[1];
  return Coord{static_cast<std::int32_t>(key % nx), static_cast<std::int32_t>((key / nx) % ny),
               static_cast<std::int32_t>(key / (nx * ny))};
}

}  // namespace poreshell
