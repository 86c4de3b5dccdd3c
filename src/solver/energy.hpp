#pragma once
// The discrete energy of eq. (3.2):
//   E^h(phi) = sum over band voxels of [ F(phi) + eps^2/2 |grad_h phi|^2 + alpha/2 |grad_h psi|^2 ] h^3,
// with psi from -Delta_h psi = phi - phi_bar on the band (ghosts by closest-point interpolation)
// and mean(psi) = 0. The Poisson operator is factorised once, so each evaluation is a back-substitution.

#include <memory>
#include <span>
#include <vector>

#include "band/band.hpp"
#include "solver/model.hpp"

namespace poreshell {

class EnergyFunctional {
 public:
  EnergyFunctional(const NarrowBand& band, const ModelParameters& model);
  ~EnergyFunctional();

  double operator()(std::span<const double> phi) const;

  // psi with -Delta_h psi = phi - phi_bar (+ the constant that makes the singular system consistent)
  // and zero mean over the band.
  std::vector<double> potential(std::span<const double> phi) const;

 private:
  struct Factor;
  const NarrowBand& band_;
  ModelParameters model_;
  std::unique_ptr<Factor> factor_;
};

}  // namespace poreshell
