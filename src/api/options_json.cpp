// The option table's text forms (include/poreshell/option_table.hpp): parsed, read by the table
// (io/option_table.cpp) and checked as every run's options are.

#include <nlohmann/json.hpp>

#include "core/error.hpp"
#include "io/option_json.hpp"
#include "poreshell/option_table.hpp"

namespace poreshell {

std::string options_to_json(const Options& options) {
  return options_json(options).dump(2);
}

Options options_from_json(std::string_view json_text) {
  const nlohmann::json settings = nlohmann::json::parse(json_text, nullptr, false);
  if (settings.is_discarded()) throw OptionError("", "the options are not valid JSON");
  Options options = options_from_json_object(settings);
  validate(options);
  return options;
}

}  // namespace poreshell
