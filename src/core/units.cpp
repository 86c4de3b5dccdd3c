#include "core/units.hpp"

#include <fmt/format.h>

#include <cmath>

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

std::string readable(double x) {
  const double a = std::abs(x);
  if (!std::isfinite(x) || a >= 1e15 || (a < 1e-3 && a > 0.0)) return fmt::format("{:.3g}", x);
  if (a >= 100.0) return fmt::format("{:.0f}", x);
  return fmt::format("{:.3g}", x);
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

std::optional<Unit> unit_from_name(std::string_view name) {
  for (const Unit unit : {Unit::m, Unit::cm, Unit::mm, Unit::inch})
    if (name == to_string(unit)) return unit;
  return std::nullopt;
}

}  // namespace poreshell
