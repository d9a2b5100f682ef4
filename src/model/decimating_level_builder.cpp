#include "model/decimating_level_builder.h"

#include "model/mesh_decimation.h"
#include "spectral/resolution_level.h"

namespace sc::model {

session::LevelBuilder decimatingLevelBuilder() {
  session::LevelBuilder builder;
  builder.targets = [](std::uint32_t n) {
    std::vector<std::uint32_t> targets;
    for (const int target : levelTargets(static_cast<int>(n))) targets.push_back(static_cast<std::uint32_t>(target));
    return targets;
  };
  builder.build = [](const session::HostModel& model, std::uint32_t target) {
    const DecimatedMesh low = decimateMesh(model.V, model.F, static_cast<int>(target));
    if (low.V.rows() < 3 || low.F.rows() < 1) return spectral::ResolutionLevel{};
    return spectral::resolutionLevel(model.V, model.F, model.basis.vectors, low.V, low.F);
  };
  return builder;
}

}  // namespace sc::model
