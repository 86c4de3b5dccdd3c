#include "solver/fast_solver.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "band/operators.hpp"
#include "core/error.hpp"
#include "core/parallel.hpp"

namespace poreshell {
namespace {

// Largest S the multigrid hierarchy is built for (S grows with max phi^2; |phi| <= 1.3 is generous).
constexpr double kLargestStabilisation = 2.0;
constexpr int kMaxRepeats = 4;
// S over the bound from phi^n and the guess of phi^{n+1}: their peaks creep by less than this in a step.
constexpr double kStabilisationMargin = 1.01;
// Share of the step's error bound the first of its two solves may use (the second gets the rest).
constexpr double kFirstSolveShare = 0.9;

struct Shifts {
  double z1, z2;
};

// The smallest S with real roots z1, z2 of eps^2 z^2 - S z + (1/dt + alpha) = 0.
double smallest_real_stabilisation(const ModelParameters& m, double dt) {
  return 1.0001 * 2.0 * std::sqrt(m.epsilon * m.epsilon * (1.0 / dt + m.alpha));
}

Shifts shifts_for(const ModelParameters& m, double dt, double s) {
  const double eps2 = m.epsilon * m.epsilon;
  const double c = 1.0 / dt + m.alpha;
  const double root = std::sqrt(std::max(0.0, s * s - 4.0 * eps2 * c));
  return {2.0 * c / (s + root), (s + root) / (2.0 * eps2)};  // z1 without cancellation
}

// The stabilisation that covers values up to |phi|^2 = max_square: S >= (3 max_square - 1) / 2.
double required_stabilisation(double max_square) {
  return 0.5 * (3.0 * max_square - 1.0);
}

double max_square(std::span<const double> phi) {
  return parallel_max(phi.size(), [&](std::size_t v) { return phi[v] * phi[v]; });
}

}  // namespace

FastSolver::FastSolver(const NarrowBand& band, const ModelParameters& model, double dt, FastOptions options)
    : band_(band),
      model_(model),
      dt_(dt),
      options_(options),
      multigrid_(
          (validate(model, dt), band),
          shifts_for(model, dt, std::max(kLargestStabilisation, smallest_real_stabilisation(model, dt))).z1,
          options.progress) {
  if (!(options_.tolerance > 0.0)) throw InputError("the fast solver's tolerance must be positive");
  if (!(options_.min_stabilisation >= 0.0)) throw InputError("the stabilisation floor must be >= 0");
  multigrid_.set_progress(options_.cycles);
  extended_.assign(band.extended_size(), 0.0);
  rhs_.assign(band.size(), 0.0);
  y_.assign(band.size(), 0.0);
  guess_image_.assign(band.size(), 0.0);
  set_stabilisation(1.0);
}

void FastSolver::set_mean_field(std::vector<double> phi_bar) {
  if (phi_bar.size() != band_.size()) throw std::invalid_argument("one mean concentration per band voxel");
  mean_field_ = std::move(phi_bar);
}

void FastSolver::set_stabilisation(double s) {
  s_ = std::max({s, options_.min_stabilisation, smallest_real_stabilisation(model_, dt_)});
  const Shifts z = shifts_for(model_, dt_, s_);
  z1_ = z.z1;
  z2_ = z.z2;
}

std::size_t FastSolver::memory_bytes() const {
  return multigrid_.memory_bytes() +
         (extended_.capacity() + rhs_.capacity() + y_.capacity() + guess_image_.capacity() + old_.capacity() +
          previous_.capacity() + second_previous_.capacity() + mean_field_.capacity()) *
             sizeof(double);
}

StepReport FastSolver::step(std::vector<double>& phi) {
  if (phi.size() != band_.size()) throw std::invalid_argument("phi must have one value per band voxel");
  old_ = phi;
  const double old_square = max_square(old_);
  // S covers the guess of phi^{n+1} as well as phi^n, with a margin: with S from phi^n alone the
  // growing or creeping peaks of the pattern made every fifth step a repeat (bunny, N = 260).
  guess_next(phi);
  set_stabilisation(kStabilisationMargin * required_stabilisation(std::max(old_square, max_square(phi))));
  StepReport report;
  for (int attempt = 0;; ++attempt) {
    if (attempt > 0) guess_next(phi);
    const StepReport r = solve_step(old_, phi);
    report.inner_iterations += r.inner_iterations;
    report.residual = r.residual;
    report.converged = r.converged;
    const double needed = required_stabilisation(std::max(old_square, max_square(phi)));
    if (needed <= s_ || attempt == kMaxRepeats || !std::isfinite(needed)) break;
    ++report.repeats;
    set_stabilisation(1.05 * needed);
  }
  std::swap(second_previous_, previous_);  // the history for the next step's guess
  std::swap(previous_, old_);
  ++steps_;
  return report;
}

// Initial guess of phi^{n+1}: extrapolated from the last three steps, 3 phi^n - 3 phi^{n-1} + phi^{n-2}
// (fewer in the first two steps). The pattern moves smoothly from step to step, so the guess is nearly
// the solution; quadratic instead of linear extrapolation took the bunny at N = 131 from 689 to 489
// V-cycles (the sphere from 717 to 563), cubic was no better on the sphere.
void FastSolver::guess_next(std::vector<double>& phi) const {
  const std::size_t n = band_.size();
  if (steps_ >= 2)
    tbb::parallel_for(std::size_t{0}, n,
                      [&](std::size_t v) { phi[v] = 3.0 * (old_[v] - previous_[v]) + second_previous_[v]; });
  else if (steps_ == 1)
    tbb::parallel_for(std::size_t{0}, n, [&](std::size_t v) { phi[v] = 2.0 * old_[v] - previous_[v]; });
  else
    std::copy(old_.begin(), old_.end(), phi.begin());
}

StepReport FastSolver::solve_step(std::span<const double> phi_old, std::vector<double>& phi) {
  const std::size_t n = band_.size();
  const double eps2 = model_.epsilon * model_.epsilon;

  // rhs = (phi^n + alpha dt phi_bar + dt L((phi^n)^3 - (1 + S) phi^n)) / (eps^2 dt)
  tbb::parallel_for(std::size_t{0}, n, [&](std::size_t v) {
    const double p = phi_old[v];
    extended_[v] = p * p * p - (1.0 + s_) * p;
  });
  band_.fill_ghosts(extended_);
  apply_laplacian(band_, extended_, rhs_);
  tbb::parallel_for(std::size_t{0}, n, [&](std::size_t v) {
    const double phi_bar = mean_field_.empty() ? model_.phi_bar : mean_field_[v];
    rhs_[v] = (phi_old[v] + dt_ * model_.alpha * phi_bar + dt_ * rhs_[v]) / (eps2 * dt_);
  });

  // y = (z2 - L) phi from the guess of phi^{n+1} in phi. Kept as the guess's image too: the second
  // solve's first residual is then y - image, with no operator pass (the same value to the bit).
  std::copy(phi.begin(), phi.end(), extended_.begin());
  band_.fill_ghosts(extended_);
  apply_laplacian(band_, extended_, guess_image_);
  tbb::parallel_for(std::size_t{0}, n, [&](std::size_t v) {
    guess_image_[v] = z2_ * phi[v] - guess_image_[v];
    y_[v] = guess_image_[v];
  });

  // Error bound in phi (max norm): |r1| / (z1 z2) + |r2| / z2 <= tolerance. The first solve may use
  // most of it and the second gets what the first left: a V-cycle cuts the residual about 10x, so the
  // first usually ends well inside its share and leaves the second more than a fixed half, which then
  // often needs one cycle fewer. Against halves (bunny, sphere, torus at N = 131): 494 -> 438,
  // 590 -> 568 and 881 -> 814 V-cycles, the same steps and spots.
  const MultigridSolveReport first =
      multigrid_.solve(z1_, rhs_, y_, kFirstSolveShare * options_.tolerance * z1_ * z2_, options_.max_cycles);
  // The second keeps at least its own share where the first stopped at max_cycles short of its target.
  const double left = options_.tolerance - first.residual / (z1_ * z2_);
  const MultigridSolveReport second =
      multigrid_.solve(z2_, y_, phi, std::max(left, (1.0 - kFirstSolveShare) * options_.tolerance) * z2_,
                       options_.max_cycles, guess_image_);
  StepReport report;
  report.inner_iterations = first.cycles + second.cycles;
  report.residual = first.residual / (z1_ * z2_) + second.residual / z2_;
  report.converged = first.converged && second.converged;
  return report;
}

}  // namespace poreshell
