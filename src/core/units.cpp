#include "core/units.hpp"

namespace poreshell {

double millimetres_per(Unit unit) {
  switch (unit) {
    case Unit::m:
      return 1000.0;
    case Unit::cm:
      return 10.0;
    case Unit::inch:
      return 25.4;
    case Unit::mm:
      break;
  }
  return 1.0;
}

std::optional<Unit> fitting_unit(double longest, Unit current) {
  for (const Unit u : {Unit::mm, Unit::cm, Unit::inch, Unit::m}) {
    const double mm = longest * millimetres_per(u);
    if (u != current && mm >= kGoodLowMm && mm <= kGoodHighMm) return u;
  }
  return std::nullopt;
}

const char* to_string(Unit unit) {
  switch (unit) {
    case Unit::m:
      return "m";
    case Unit::cm:
      return "cm";
    case Unit::inch:
      return "inch";
    case Unit::mm:
      break;
  }
  return "mm";
}

}  // namespace poreshell
