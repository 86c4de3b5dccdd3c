#pragma once
// The machine-readable report of a run (the CLI's --report).

#include <nlohmann/json.hpp>

#include "pipeline/pipeline.hpp"

namespace poreshell {

nlohmann::json to_json(const PipelineResult& result);

}  // namespace poreshell
