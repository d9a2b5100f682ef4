#pragma once
// How a host builds its display levels (docs/protocol.md, "Levels"), handed in by the application so that session
// does not include model/. Both functions speak spectral and standard types only, so the model layer can supply them
// without knowing the session: the app writes `options.levelBuilder = {model::levelTargetList,
// model::decimatedLevel}` (model/decimating_level_builder.h).
//
// Contract: `targets(n)` lists the ladder's vertex counts for a model of n vertices (any order, duplicates and
// values ≥ n are dropped by the user); `build(V, F, H, target)` builds the level of about `target` vertices
// (target < n) with its K = P·H. A level of fewer than 3 vertices or no face counts as a failed build; an
// exception is caught and reported as a failure. `build` runs on the host's level-building thread: it must not
// touch state shared with other threads. An empty LevelBuilder (either function empty) means no ladder: the host
// serves the full model only.

#include "spectral/resolution_level.h"

#include <Eigen/Core>

#include <cstdint>
#include <functional>
#include <vector>

namespace sc::session {

struct LevelBuilder {
  std::function<std::vector<std::uint32_t>(std::uint32_t n)> targets;
  /// V (n by 3), F (#F by 3): the full rest mesh; H (n by m): its basis.
  std::function<spectral::ResolutionLevel(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const Eigen::MatrixXd& H,
                                          std::uint32_t target)>
      build;

  [[nodiscard]] bool empty() const { return !targets || !build; }
  /// targets(n), or none for an empty builder.
  [[nodiscard]] std::vector<std::uint32_t> targetsFor(std::uint32_t n) const {
    return empty() ? std::vector<std::uint32_t>{} : targets(n);
  }
};

}  // namespace sc::session
