#pragma once
// Length units of inputs (include/poreshell/geometry.hpp). Every output is in millimetres.

#include <optional>
#include <string>

#include "poreshell/geometry.hpp"

namespace poreshell {

// The size most prints have, in mm: a model outside it is often in another unit.
inline constexpr double kGoodLowMm = 20.0, kGoodHighMm = 500.0;
// The unit that would make a model `longest` input units across kGoodLowMm to kGoodHighMm, if one does.
std::optional<Unit> fitting_unit(double longest, Unit current);

// A length or size as a person reads it: 3 significant digits, whole numbers from 100 up, no exponent
// from 0.001 to 10^15 ("5080", "31.7", "0.785"; issue 47: "5.08e+03 mm").
std::string readable(double x);

}  // namespace poreshell
