#pragma once
// Discrete operators of section 2 on the band: the 7-point Laplacian Delta_h and the central
// gradient grad_h. Values live in "extended" arrays: band entries followed by ghost entries.

#include <Eigen/SparseCore>
#include <span>

#include "band/band.hpp"

namespace poreshell {

using SparseMatrix = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;

// out[v] = Delta_h u at band voxel v, for an extended array whose ghosts are filled.
void apply_laplacian(const NarrowBand& band, std::span<const double> extended, std::span<double> out);

// |grad_h u|^2 at band voxel v with central differences (1/2h); ghosts must be filled.
inline double central_gradient_norm2(const NarrowBand& band, std::span<const double> extended,
                                     std::size_t v) {
  double g2 = 0.0;
  for (int a = 0; a < 3; ++a) {
    const double d = extended[band.neighbor(v, 2 * a + 1)] - extended[band.neighbor(v, 2 * a)];
    g2 += d * d;
  }
  const double h = band.grid().h();
  return g2 / (4.0 * h * h);
}

// Delta_h as an n x n matrix on band unknowns, ghost values eliminated through their closest-point
// stencils (ghost = sum of weights * band values). Not symmetric.
SparseMatrix laplacian_matrix(const NarrowBand& band);

}  // namespace poreshell
