#pragma once
// Length units of inputs (include/poreshell/geometry.hpp). Every output is in millimetres.

#include <optional>

#include "poreshell/geometry.hpp"

namespace poreshell {

// The size most prints have, in mm: a model outside it is often in another unit.
inline constexpr double kGoodLowMm = 20.0, kGoodHighMm = 500.0;
// The unit that would make a model `longest` input units across kGoodLowMm to kGoodHighMm, if one does.
std::optional<Unit> fitting_unit(double longest, Unit current);

}  // namespace poreshell
