#include "solver/reference_solver.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "core/error.hpp"
#include "core/parallel.hpp"

namespace poreshell {

std::string to_string(InnerIteration it) {
  switch (it) {
    case InnerIteration::jacobi:
      return "jacobi";
    case InnerIteration::gauss_seidel:
      return "gauss-seidel";
  }
  return "?";
}

EquationResidual equation_residual(const NarrowBand& band, const SparseMatrix& laplacian,
                                   const ModelParameters& model, double dt, std::span<const double> phi_old,
                                   std::span<const double> phi, std::span<const double> mu) {
  const auto n = static_cast<Eigen::Index>(band.size());
  const Eigen::Map<const Eigen::VectorXd> p(phi.data(), n), m(mu.data(), n);
  const Eigen::VectorXd lap_mu = laplacian * m;
  const Eigen::VectorXd lap_phi = laplacian * p;
  const double eps2 = model.epsilon * model.epsilon;
  EquationResidual r;
  r.phi = parallel_max(band.size(), [&](std::size_t v) {
    const auto i = static_cast<Eigen::Index>(v);
    return std::abs(phi[v] - phi_old[v] - dt * lap_mu[i] + dt * model.alpha * (phi[v] - model.phi_bar));
  });
  r.mu = parallel_max(band.size(), [&](std::size_t v) {
    const auto i = static_cast<Eigen::Index>(v);
    return std::abs(mu[v] - phi[v] * phi[v] * phi[v] + phi_old[v] + eps2 * lap_phi[i]);
  });
  return r;
}

ReferenceSolver::ReferenceSolver(const NarrowBand& band, const ModelParameters& model, double dt,
                                 InnerOptions inner)
    : band_(band), model_(model), dt_(dt), inner_(inner), laplacian_(laplacian_matrix(band)) {
  validate(model, dt);
  if (!(inner_.tolerance > 0.0)) throw InputError("the inner tolerance must be positive");
  if (inner_.max_iterations <= 0) inner_.max_iterations = 200000;
  mu_.assign(band.extended_size(), 0.0);
  if (inner_.method == InnerIteration::gauss_seidel)
    for (std::size_t v = 0; v < band.size(); ++v) {
      const Coord c = band.voxels()[v];
      colours_[(c.i + c.j + c.k) & 1].push_back(v);
    }
}

void ReferenceSolver::initialise_mu(std::span<const double> phi) {
  // mu consistent with phi at rest: phi^3 - phi - eps^2 Delta_h phi.
  const auto n = static_cast<Eigen::Index>(band_.size());
  const Eigen::VectorXd lap = laplacian_ * Eigen::Map<const Eigen::VectorXd>(phi.data(), n);
  const double eps2 = model_.epsilon * model_.epsilon;
  for (Eigen::Index i = 0; i < n; ++i) {
    const double p = phi[static_cast<std::size_t>(i)];
    mu_[static_cast<std::size_t>(i)] = p * p * p - p - eps2 * lap[i];
  }
  mu_ready_ = true;
}

StepReport ReferenceSolver::step(std::vector<double>& phi) {
  if (phi.size() != band_.size()) throw std::invalid_argument("phi must have one value per band voxel");
  if (!mu_ready_) initialise_mu(phi);
  return relaxation_step(phi, inner_.method == InnerIteration::gauss_seidel);
}

StepReport ReferenceSolver::relaxation_step(std::vector<double>& phi, bool red_black) {
  const std::size_t n = band_.size();
  const double h2 = band_.grid().h() * band_.grid().h();
  const double eps2 = model_.epsilon * model_.epsilon;
  const double a = 1.0 + dt_ * model_.alpha, b = 6.0 * dt_ / h2;
  const std::vector<double> phi_old = phi;
  std::vector<double> p(band_.extended_size()), p_next, m_next;
  std::copy(phi.begin(), phi.end(), p.begin());
  band_.fill_ghosts(p);
  band_.fill_ghosts(mu_);
  if (!red_black) {
    p_next = p;
    m_next = mu_;
  }

  // One pointwise update: the cubic term linearised about the current value, neighbours lagged, and the
  // 2x2 system in (phi_v, mu_v) solved exactly.
  auto relax = [&](std::size_t v, const std::vector<double>& pin, const std::vector<double>& min,
                   double& pout, double& mout) {
    double sp = 0.0, sm = 0.0;
    for (int k = 0; k < NarrowBand::kNeighbors; ++k) {
      const auto nb = static_cast<std::size_t>(band_.neighbor(v, k));
      sp += pin[nb];
      sm += min[nb];
    }
    const double star = pin[v];
    const double c = -(3.0 * star * star + 6.0 * eps2 / h2);
    const double r1 = phi_old[v] + dt_ * model_.alpha * model_.phi_bar + dt_ * sm / h2;
    const double r2 = -2.0 * star * star * star - phi_old[v] - eps2 * sp / h2;
    const double det = a - b * c;
    pout = (r1 - b * r2) / det;
    mout = (a * r2 - c * r1) / det;
  };

  StepReport report;
  constexpr int kCheckEvery = 10;
  for (int sweep = 1;; ++sweep) {
    if (red_black) {
      for (const auto& set : colours_) {
        tbb::parallel_for(std::size_t{0}, set.size(), [&](std::size_t s) {
          const std::size_t v = set[s];
          double pv, mv;
          relax(v, p, mu_, pv, mv);
          p[v] = pv;
          mu_[v] = mv;
        });
        band_.fill_ghosts(p);
        band_.fill_ghosts(mu_);
      }
    } else {
      tbb::parallel_for(std::size_t{0}, n, [&](std::size_t v) { relax(v, p, mu_, p_next[v], m_next[v]); });
      std::swap(p, p_next);
      std::swap(mu_, m_next);
      band_.fill_ghosts(p);
      band_.fill_ghosts(mu_);
    }
    if (sweep % kCheckEvery != 0 && sweep < inner_.max_iterations) continue;
    report.inner_iterations = sweep;
    report.residual =
        equation_residual(band_, laplacian_, model_, dt_, phi_old, {p.data(), n}, {mu_.data(), n}).max();
    if (report.residual < inner_.tolerance) break;
    if (sweep >= inner_.max_iterations || !std::isfinite(report.residual)) {
      report.converged = false;
      break;
    }
  }
  std::copy(p.begin(), p.begin() + static_cast<std::ptrdiff_t>(n), phi.begin());
  return report;
}

}  // namespace poreshell
