#pragma once
// The fast default solver (docs/solver.md): the paper's equations with the cubic term lagged and a
// linear stabilisation S (phi^{n+1} - phi^n) in the chemical potential,
//   (phi^{n+1} - phi^n)/dt = Delta_h mu - alpha (phi^{n+1} - phi_bar)
//   mu = (phi^n)^3 - phi^n + S (phi^{n+1} - phi^n) - eps^2 Delta_h phi^{n+1},
// i.e. one linear system per step,
//   P = (1 + alpha dt) - S dt L + eps^2 dt L^2 = eps^2 dt (z1 - L)(z2 - L),
// z1 z2 = (1/dt + alpha)/eps^2 and z1 + z2 = S/eps^2, solved as two shifted closest-point Laplacian
// solves by band multigrid. A steady state of this scheme is a steady state of the paper's equations
// (the S term vanishes when phi^{n+1} = phi^n).
//
// S is chosen every step just above the smallest value the energy-stability argument allows: S >= f'(xi)/2
// for every xi between phi^n and phi^{n+1} at every voxel, f' = 3 phi^2 - 1 (Shen and Yang 2010), with
// phi^{n+1} predicted by the step's initial guess. A larger S slows the growth of the pattern: with
// S = 1 throughout, the spinodal phase is about 1.7 times slower than in the paper's scheme and the
// stopping rule can fire before the pattern forms. A step that ends outside the range its S covers is
// repeated with a larger S.

#include <memory>
#include <vector>

#include "solver/band_multigrid.hpp"
#include "solver/model.hpp"
#include "solver/time_stepper.hpp"

namespace poreshell {

struct FastOptions {
  double min_stabilisation = 0.0;  // floor on S (the stability bound and real shifts apply regardless)
  double tolerance = 1e-3;         // max-norm bound on the error of phi^{n+1} from the linear solves
  int max_cycles = 60;             // V-cycles per shifted solve
  StageProgress progress{};        // the set-up's share of its stage (the multigrid hierarchy)
  StageProgress cycles{};          // checked before every V-cycle (a share of none: fraction unchanged)
};

class FastSolver final : public TimeStepper {
 public:
  FastSolver(const NarrowBand& band, const ModelParameters& model, double dt, FastOptions options = {});

  StepReport step(std::vector<double>& phi) override;
  std::string name() const override { return "fast"; }

  // A mean concentration per band voxel instead of the model's phi_bar (solid zones: rims, keep-outs).
  void set_mean_field(std::vector<double> phi_bar);

  // The stabilisation and shifts of the last step.
  double stabilisation() const { return s_; }
  double shift_small() const { return z1_; }
  double shift_large() const { return z2_; }
  const BandMultigrid& multigrid() const { return multigrid_; }
  std::size_t memory_bytes() const;

 private:
  void set_stabilisation(double s);
  void guess_next(std::vector<double>& phi) const;
  // phi: the guess in, phi^{n+1} out.
  StepReport solve_step(std::span<const double> phi_old, std::vector<double>& phi);

  const NarrowBand& band_;
  ModelParameters model_;
  double dt_;
  FastOptions options_;
  double s_ = 1.0, z1_ = 0.0, z2_ = 0.0;
  BandMultigrid multigrid_;
  std::vector<double> extended_;                          // band + ghosts scratch
  std::vector<double> rhs_, y_;                           // y = (z2 - L) phi^{n+1}
  std::vector<double> guess_image_;                       // (z2 - L) of the step's guess of phi^{n+1}
  std::vector<double> mean_field_;                        // empty: the model's phi_bar everywhere
  std::vector<double> old_, previous_, second_previous_;  // phi^n, phi^{n-1}, phi^{n-2}: the guess
  int steps_ = 0;
};

}  // namespace poreshell
