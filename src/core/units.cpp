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
