#include "solver/model.hpp"

#include "core/error.hpp"

namespace poreshell {

void validate(const ModelParameters& p, double dt) {
  if (!(p.alpha >= 0.0) || !std::isfinite(p.alpha)) throw InputError("alpha must be a finite number >= 0");
  if (!(p.epsilon > 0.0) || !std::isfinite(p.epsilon))
    throw InputError("epsilon must be a positive finite number");
  if (!(std::abs(p.phi_bar) < 1.0)) throw InputError("phi-bar must lie strictly between -1 and 1");
  if (!(dt > 0.0) || !std::isfinite(dt)) throw InputError("the time step must be a positive finite number");
}

}  // namespace poreshell
