#pragma once
// What a session host serves: the cleaned full-resolution mesh, its manifold harmonic basis and its Laplace
// operators. Shared, immutable, between the host's deformer (which keeps references into it), its level builder
// thread and whoever loaded it; hold it by std::shared_ptr<const HostModel> so that it outlives all of them.

#include "spectral/harmonic_basis.h"
#include "spectral/laplace_operators.h"

#include <Eigen/Core>

namespace sc::session {

struct HostModel {
  Eigen::MatrixXd V;                     ///< #V by 3 rest positions X̂ (cleaned)
  Eigen::MatrixXi F;                     ///< #F by 3 faces, indices into V
  spectral::HarmonicBasis basis;         ///< H: #V by m, 1 ≤ m ≤ kMaxRows
  spectral::LaplaceOperators operators;  ///< S and M of (V, F): the deformer's rigid mode uses them

  [[nodiscard]] int vertexCount() const { return static_cast<int>(V.rows()); }
  [[nodiscard]] int rowCount() const { return static_cast<int>(basis.vectors.cols()); }
};

}  // namespace sc::session
