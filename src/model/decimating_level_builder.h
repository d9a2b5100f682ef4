#pragma once
// The host's display levels by decimation, as the two functions of a session::LevelBuilder
// (session/engine/level_builder.h) in spectral and standard types only, so that model does not know the session and
// the session does not include model: the app writes `options.levelBuilder = {model::levelTargetList,
// model::decimatedLevel}`.

#include "spectral/resolution_level.h"

#include <Eigen/Core>

#include <cstdint>
#include <vector>

namespace sc::model {

/// The ladder for a model of n vertices: levelTargets(n) (kDefaultLevelFractions: 50%, 20%, 5% of n), as unsigned.
/// Cost: O(ladder).
[[nodiscard]] std::vector<std::uint32_t> levelTargetList(std::uint32_t n);

/// decimateMesh() of the full mesh (V, F) to about `target` vertices, with the barycentric map and K = P·H of
/// spectral::resolutionLevel(); an empty level when the decimation leaves fewer than 3 vertices or no face (the
/// host counts it as a failed build).
/// Cost: one decimation plus the barycentric map, O(#F log #F + n'·m). Thread-safe (meshoptimizer keeps no global
/// state); the host runs one build at a time on its level thread.
[[nodiscard]] spectral::ResolutionLevel decimatedLevel(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                                                       const Eigen::MatrixXd& H, std::uint32_t target);

}  // namespace sc::model
