#pragma once
// The interface every solver of the time-discrete equations implements, so that the driver,
// the CLI and the tests do not care which one runs.

#include <span>
#include <string>
#include <vector>

namespace poreshell {

struct StepReport {
  int inner_iterations = 0;  // Newton steps or relaxation sweeps
  double residual = 0.0;     // max-norm residual of the discrete equations after the step
  bool converged = true;     // inner tolerance reached
  int repeats = 0;           // times the step was solved again (the fast solver's stabilisation)
};

class TimeStepper {
 public:
  virtual ~TimeStepper() = default;
  // Advances band values phi^n -> phi^{n+1} in place.
  virtual StepReport step(std::vector<double>& phi) = 0;
  virtual std::string name() const = 0;
};

}  // namespace poreshell
