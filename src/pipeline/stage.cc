#include "pipeline/stage.h"

#include <chrono>

#include "core/check.h"

namespace mocap::pipeline {

nlohmann::json Shard::ToJson() const {
  if (whole()) return nullptr;
  return {{"index", index}, {"count", count}, {"begin", begin}, {"end", end}};
}

StageSeconds RunStages(const std::vector<Stage>& stages, PipelineContext& context, const Shard& shard) {
  StageSeconds seconds;
  for (const Stage& stage : stages) {
    if (stage.inputs)
      for (const std::filesystem::path& input : stage.inputs(context))
        if (!std::filesystem::exists(input))
          throw InputError(input.string(), Str("stage '", stage.name, "' needs it and it does not exist"));
    const auto start = std::chrono::steady_clock::now();
    stage.run(context, shard);
    seconds.emplace_back(stage.name, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  }
  return seconds;
}

}  // namespace mocap::pipeline
