#pragma once
// The option table's JSON on nlohmann::json values (include/poreshell/option_table.hpp has the text
// forms): the report's `settings`, project files and the studio's requests.

#include <nlohmann/json.hpp>

#include "poreshell/options.hpp"

namespace poreshell {

nlohmann::json options_json(const Options& options);
// Throws Error (invalid_option) naming the option; validate() is the caller's.
Options options_from_json_object(const nlohmann::json& settings);

}  // namespace poreshell
