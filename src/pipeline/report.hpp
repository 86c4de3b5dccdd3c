#pragma once
// The run's report as the public struct (include/poreshell/result.hpp), from the pipeline's result.

#include "pipeline/pipeline.hpp"
#include "poreshell/result.hpp"

namespace poreshell {

Report make_report(const PipelineResult& result, const Options& options);

}  // namespace poreshell
