#pragma once
// The paper's scheme, eqs. (2.3)-(2.4), as the reference:
//   (phi^{n+1} - phi^n)/dt = Delta_h mu^{n+1} - alpha (phi^{n+1} - phi_bar)
//   mu^{n+1} = (phi^{n+1})^3 - phi^n - eps^2 Delta_h phi^{n+1}
// with ghost values of phi and mu from closest-point interpolation. The reference is the solution of
// these equations to the inner tolerance, reached by pointwise relaxation as in the paper: each sweep
// solves the 2x2 system in (phi_v, mu_v) at every voxel with the cubic term linearised about the current
// value and the neighbours lagged, then refreshes the ghosts.
//   gauss-seidel  red-black order (default): about half the sweeps of Jacobi, same fixed point
//   jacobi        the paper's order
// A Newton iteration with a sparse direct solve was measured and rejected (docs/solver.md): UMFPACK
// with the reference BLAS took about 5 s per factorisation on a 17k-voxel band.

#include <memory>
#include <span>
#include <vector>

#include "band/band.hpp"
#include "band/operators.hpp"
#include "poreshell/options.hpp"
#include "solver/model.hpp"
#include "solver/time_stepper.hpp"

namespace poreshell {

std::string to_string(InnerIteration it);

struct InnerOptions {
  InnerIteration method = InnerIteration::gauss_seidel;
  double tolerance = 1e-8;  // max-norm of the scaled residual (see equation_residual)
  int max_iterations = 0;   // sweeps per step; 0: 200000
};

// Max-norm residuals of the two equations, scaled to O(1) quantities:
//   r_phi = phi - phi^n - dt Delta_h mu + dt alpha (phi - phi_bar),
//   r_mu  = mu - phi^3 + phi^n + eps^2 Delta_h phi.
struct EquationResidual {
  double phi = 0.0, mu = 0.0;
  double max() const { return phi > mu ? phi : mu; }
};

EquationResidual equation_residual(const NarrowBand& band, const SparseMatrix& laplacian,
                                   const ModelParameters& model, double dt, std::span<const double> phi_old,
                                   std::span<const double> phi, std::span<const double> mu);

class ReferenceSolver final : public TimeStepper {
 public:
  ReferenceSolver(const NarrowBand& band, const ModelParameters& model, double dt, InnerOptions inner = {});

  StepReport step(std::vector<double>& phi) override;
  std::string name() const override { return "reference"; }

  std::span<const double> mu() const { return {mu_.data(), band_.size()}; }
  const SparseMatrix& laplacian() const { return laplacian_; }

 private:
  StepReport relaxation_step(std::vector<double>& phi, bool red_black);
  void initialise_mu(std::span<const double> phi);

  const NarrowBand& band_;
  ModelParameters model_;
  double dt_;
  InnerOptions inner_;
  SparseMatrix laplacian_;
  std::vector<std::size_t> colours_[2];  // red-black sets of band voxels (gauss-seidel only)
  std::vector<double> mu_;               // extended (band + ghosts), kept between steps as the warm start
  bool mu_ready_ = false;
};

}  // namespace poreshell
