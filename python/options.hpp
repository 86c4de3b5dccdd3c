#pragma once
// Options of the library from Python keyword arguments (python/options.cpp).

#include <pybind11/pybind11.h>

#include <string>
#include <vector>

#include "poreshell/options.hpp"

namespace poreshell_python {

// The Options that perforate(**kwargs) asks for: each keyword by its API name, checked (ValueError naming
// it), an unknown one a TypeError naming `caller`, and the whole validated as the library does.
poreshell::Options to_options(const pybind11::dict& kwargs, const std::string& caller = "perforate");
// Every keyword to_options takes.
std::vector<std::string> option_names();

}  // namespace poreshell_python
