#include "band/operators.hpp"

#include <tbb/parallel_for.h>

#include <vector>

namespace poreshell {

void apply_laplacian(const NarrowBand& band, std::span<const double> extended, std::span<double> out) {
  const double inv_h2 = 1.0 / (band.grid().h() * band.grid().h());
  tbb::parallel_for(std::size_t{0}, band.size(), [&](std::size_t v) {
    double sum = 0.0;
    for (int n = 0; n < NarrowBand::kNeighbors; ++n) sum += extended[band.neighbor(v, n)];
    out[v] = (sum - 6.0 * extended[v]) * inv_h2;
  });
}

SparseMatrix laplacian_matrix(const NarrowBand& band) {
  const auto n = static_cast<std::int64_t>(band.size());
  const double inv_h2 = 1.0 / (band.grid().h() * band.grid().h());
  std::vector<Eigen::Triplet<double, int>> entries;
  entries.reserve(band.size() * 12);
  const auto stencils = band.stencils();
  for (std::int64_t v = 0; v < n; ++v) {
    const int row = static_cast<int>(v);
    entries.emplace_back(row, row, -6.0 * inv_h2);
    for (int k = 0; k < NarrowBand::kNeighbors; ++k) {
      const std::int32_t nb = band.neighbor(static_cast<std::size_t>(v), k);
      if (nb < n) {
        entries.emplace_back(row, nb, inv_h2);
        continue;
      }
      const GhostStencil& s = stencils[static_cast<std::size_t>(nb - n)];
      for (int c = 0; c < 8; ++c)
        if (s.weight(c) != 0.0) entries.emplace_back(row, s.corner(c), s.weight(c) * inv_h2);
    }
  }
  SparseMatrix L(static_cast<int>(n), static_cast<int>(n));
  L.setFromTriplets(entries.begin(), entries.end());  // duplicates are summed
  return L;
}

}  // namespace poreshell
