#include "model/decimating_level_builder.h"

#include "model/mesh_decimation.h"

namespace sc::model {

std::vector<std::uint32_t> levelTargetList(std::uint32_t n) {
  std::vector<std::uint32_t> targets;
  for (const int target : levelTargets(static_cast<int>(n))) targets.push_back(static_cast<std::uint32_t>(target));
  return targets;
}

spectral::ResolutionLevel decimatedLevel(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const Eigen::MatrixXd& H,
                                         std::uint32_t target) {
  const DecimatedMesh low = decimateMesh(V, F, static_cast<int>(target));
  if (low.V.rows() < 3 || low.F.rows() < 1) return spectral::ResolutionLevel{};
  return spectral::resolutionLevel(V, F, H, low.V, low.F);
}

}  // namespace sc::model
