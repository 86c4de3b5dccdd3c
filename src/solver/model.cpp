#include "solver/model.hpp"

#include "core/error.hpp"

namespace poreshell {

void validate(const ModelParameters& p, double dt) {
  if (!(p.alpha >= 0.0) || !std::isfinite(p.alpha))
    throw OptionError("alpha", "`alpha` must be a finite number >= 0");
  if (!(p.epsilon > 0.0) || !std::isfinite(p.epsilon))
    throw OptionError("epsilon_m", "epsilon (`epsilon_m`) must be a positive finite number");
  if (!(std::abs(p.phi_bar) < 1.0))
    throw OptionError("phi_bar", "`phi_bar` must lie strictly between -1 and 1");
  if (!(dt > 0.0) || !std::isfinite(dt))
    throw OptionError("dt_h", "the time step (`dt_h`) must be a positive finite number");
}

}  // namespace poreshell
