#include "core/units.hpp"

#include "core/error.hpp"

namespace poreshell {

double millimetres_per_unit(const std::string& unit) {
  if (unit == "mm") return 1.0;
  if (unit == "cm") return 10.0;
  if (unit == "m") return 1000.0;
  if (unit == "inch") return 25.4;
  throw InputError("unknown --units '" + unit +
                   "': use m, cm, mm or inch (the unit of the input's coordinates)");
}

}  // namespace poreshell
