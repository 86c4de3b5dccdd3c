#pragma once
// The report as JSON (the fields README.md lists under Outputs).

#include <nlohmann/json.hpp>
#include <span>

#include "poreshell/result.hpp"

namespace poreshell {

// `outputs` adds each level's hole table (mesh.holes and mesh.outputs[i].holes_table).
nlohmann::json to_json(const Report& report, std::span<const Output> outputs = {});
nlohmann::json to_json(std::span<const Hole> holes);

}  // namespace poreshell
