#pragma once
// The option table's ranges (include/poreshell/option_table.hpp) as checks, in one place for a JSON value
// (option_table.cpp) and for an Options however it was made (validate()).

#include <string>

#include "poreshell/option_table.hpp"
#include "poreshell/options.hpp"

namespace poreshell {

// Finite and within the row's range, each end included unless the row says it is open.
bool in_range(const OptionInfo& info, double x);
// What the row takes: "a number in mm, at least 0", "a whole number, from 9 to 2048", ...
std::string expected(const OptionInfo& info);
// Throws OptionError naming the option, its range and its help unless every number the row's field holds
// in `options` is in range; nothing for a row with no range (choices, text, keep-outs, the grade). A NaN
// where the default is NaN (the rim's "not given") passes.
void check_range(const OptionInfo& info, const Options& options);

}  // namespace poreshell
