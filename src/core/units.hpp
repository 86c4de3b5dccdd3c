#pragma once
// Length units of input files. The command line and every output are in millimetres; the input
// file's coordinates may be in another unit, named by --units.

#include <string>

namespace poreshell {

// Millimetres per unit for "m", "cm", "mm" or "inch". Throws InputError for anything else.
double millimetres_per_unit(const std::string& unit);

}  // namespace poreshell
