#pragma once
// Parameters of the nonlocal Cahn-Hilliard model, eq. (2.1).

#include <cmath>
#include <string>

namespace poreshell {

struct ModelParameters {
  double alpha = 1400.0;  // nonlocal strength alpha
  double epsilon = 0.0;   // interface parameter epsilon
  double phi_bar = -0.3;  // mean concentration phi-bar (sets the pore fraction)
};

// epsilon_m = m h / (2 sqrt(2) atanh(0.9)): an m h wide transition layer when alpha = 0 (section 3).
inline double epsilon_m(double m, double h) {
  return m * h / (2.0 * std::sqrt(2.0) * std::atanh(0.9));
}

// F(phi) = (phi^2 - 1)^2 / 4.
inline double double_well(double phi) {
  const double s = phi * phi - 1.0;
  return 0.25 * s * s;
}

// Checks the parameters and throws InputError naming the bad one.
void validate(const ModelParameters& p, double dt);

}  // namespace poreshell
