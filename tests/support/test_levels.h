#pragma once
// A generated resolution level for tests and fuzz seeds: an icosphere's rest mesh with P mapping display vertex i to
// full-resolution vertices i (weight 0.75) and (i + 1) mod n (weight 0.25), and a given basis quantised into K. Header
// only: the includer links shapecast_spectral (this support library does not).

#include "spectral/resolution_level.h"
#include "test_meshes.h"

#include <Eigen/Core>

namespace sc::testing {

/// The icosphere of `subdivisions` as a level whose K is `basis` (n rows, n = the icosphere's vertex count) quantised.
inline spectral::ResolutionLevel icosphereLevel(int subdivisions, const Eigen::MatrixXd& basis) {
  const GeneratedMesh mesh = icosphere(subdivisions);
  spectral::ResolutionLevel level;
  level.restV = mesh.V;
  level.F = mesh.F;
  const auto n = static_cast<int>(mesh.V.rows());
  level.P.resize(n, n);
  for (int i = 0; i < n; ++i) {
    level.P.insert(i, i) = 0.75;
    level.P.insert(i, (i + 1) % n) = 0.25;
  }
  level.P.makeCompressed();
  level.K = spectral::quantizeBasis(basis);
  return level;
}

}  // namespace sc::testing
