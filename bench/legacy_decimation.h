#pragma once
// The project's own decimater before meshoptimizer replaced it in src/model (issue 19): OpenMesh's halfedge mesh,
// Garland–Heckbert quadrics with boundary planes, Wu & Kobbelt multiple-choice collapses on large meshes then a
// priority queue, non-manifold faces refused by the halfedge mesh carried through the exact collapse chains.
// Kept only as the "before" of shapecast-bench-decimation; the product does not link it.

#include "model/mesh_decimation.h"

#include <Eigen/Core>

#include <vector>

namespace sc::bench::legacy {

/// As model::resolutionLadder() did before issue 19. Cost: O(#F log #F), ≈ 10 µs per collapse on large meshes.
std::vector<model::DecimatedMesh> resolutionLadder(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                                                   const std::vector<int>& targets);

/// As model::decimateMesh() did before issue 19 (one level).
model::DecimatedMesh decimateMesh(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, int targetVertices);

}  // namespace sc::bench::legacy
