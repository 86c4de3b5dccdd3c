#include "solver/energy.hpp"

#include <Eigen/UmfPackSupport>

#include <stdexcept>

#include "band/operators.hpp"
#include "core/parallel.hpp"

namespace poreshell {

// -Delta_h is singular (constants are in its kernel). Bordering it with the mean constraint,
//   [ -L  1 ] [psi]   [f]
//   [ 1^T 0 ] [lam] = [0],
// gives a regular system whose psi has zero mean; lam absorbs the part of f outside the range of L
// (the closest-point Laplacian is not symmetric, so its range is not exactly the zero-mean vectors).
struct EnergyFunctional::Factor {
  SparseMatrix matrix;  // UmfPackLU keeps pointers into the matrix it factorised
  Eigen::UmfPackLU<SparseMatrix> lu;
};

EnergyFunctional::EnergyFunctional(const NarrowBand& band, const ModelParameters& model)
    : band_(band), model_(model), factor_(std::make_unique<Factor>()) {
  const SparseMatrix L = laplacian_matrix(band);
  const int n = static_cast<int>(band.size());
  std::vector<Eigen::Triplet<double, int>> t;
  t.reserve(static_cast<std::size_t>(L.nonZeros() + 2 * n));
  const double scale = band.grid().h() * band.grid().h();  // keep the border entries on the scale of h^2 L
  for (int col = 0; col < n; ++col)
    for (SparseMatrix::InnerIterator it(L, col); it; ++it) t.emplace_back(it.row(), col, -scale * it.value());
  for (int i = 0; i < n; ++i) {
    t.emplace_back(i, n, 1.0);
    t.emplace_back(n, i, 1.0);
  }
  SparseMatrix& A = factor_->matrix;
  A.resize(n + 1, n + 1);
  A.setFromTriplets(t.begin(), t.end());
  A.makeCompressed();
  factor_->lu.compute(A);
  if (factor_->lu.info() != Eigen::Success)
    throw std::runtime_error("UMFPACK could not factorise the band's Poisson operator");
}

EnergyFunctional::~EnergyFunctional() = default;

std::vector<double> EnergyFunctional::potential(std::span<const double> phi) const {
  const int n = static_cast<int>(band_.size());
  const double scale = band_.grid().h() * band_.grid().h();
  Eigen::VectorXd rhs(n + 1);
  for (int i = 0; i < n; ++i) rhs[i] = scale * (phi[static_cast<std::size_t>(i)] - model_.phi_bar);
  rhs[n] = 0.0;
  const Eigen::VectorXd x = factor_->lu.solve(rhs);
  return {x.data(), x.data() + n};
}

double EnergyFunctional::operator()(std::span<const double> phi) const {
  const std::size_t n = band_.size();
  std::vector<double> p(band_.extended_size()), psi(band_.extended_size());
  std::copy(phi.begin(), phi.end(), p.begin());
  const std::vector<double> potential_values = potential(phi);
  std::copy(potential_values.begin(), potential_values.end(), psi.begin());
  band_.fill_ghosts(p);
  band_.fill_ghosts(psi);
  const double eps2 = model_.epsilon * model_.epsilon;
  const double h = band_.grid().h();
  const double sum = deterministic_sum(n, [&](std::size_t v) {
    return double_well(p[v]) + 0.5 * eps2 * central_gradient_norm2(band_, p, v) +
           0.5 * model_.alpha * central_gradient_norm2(band_, psi, v);
  });
  return sum * h * h * h;
}

}  // namespace poreshell
