#pragma once
// The rotation terms of as-rigid-as-possible deformation restricted to the harmonic subspace X = X̂ + HZ
// (shared/design/spectral.md §5; the reduction of Jacobson et al.'s "Fast Automatic Skinning Transformations").

#include "spectral/harmonic_basis.h"
#include "spectral/laplace_operators.h"

#include <Eigen/Core>

#include <vector>

namespace sc::spectral {

/// Spokes-ARAP with one rotation per vertex cluster, E = Σ_g Σ_{k∈g} Σ_j w_kj ‖e_kj − R_g ê_kj‖² (w_kj = −S_kj),
/// with every term precomputed in the subspace so that a local–global iteration costs O(9·m·r) plus r 3×3 SVDs,
/// independent of #V. Global step: (Λ + w² H_CᵀH_C) Z = rotationRightHandSide(Z) + constraint terms.
class RigidSubspace {
 public:
  /// Clusters the vertices (k-means on the rows of the first harmonics) and precomputes, per cluster g,
  /// Q_g = ½ Σ_{spokes (k,j), k∈g} w_kj (H_k − H_j)ᵀ ê_kjᵀ (m by 3) and C⁰_g = Σ w_kj ê_kj ê_kjᵀ.
  /// @param clusters  wanted cluster count r; capped at #V / 4 (at least 1).
  /// Cost: O(#V·r·d) per k-means iteration (d ≤ 10) plus O(nnz(S)·m).
  RigidSubspace(const HarmonicBasis& basis, const LaplaceOperators& operators, const Eigen::MatrixXd& rest,
                int clusters);

  /// One local step and the rotation part of the global right-hand side: with C_g = C⁰_g + 2 Zᵀ Q_g and
  /// R_g = argmax tr(R C_gᵀ) over rotations (SVD), returns Σ_g Q_g R_gᵀ − Σ_g Q_g (m by 3), i.e. the rotated-edge
  /// term minus its value at rest (Σ_g Q_g = ΛŶ = HᵀSX̂), so that Z = 0 is the fixed point when nothing moves.
  /// Cost: O(18·m·r) plus r 3×3 SVDs.
  Eigen::MatrixXd rotationRightHandSide(const Eigen::MatrixXd& Z) const;

  int clusterCount() const { return static_cast<int>(m_Q.size()); }
  /// Cluster index of every vertex.
  const Eigen::VectorXi& clusterOfVertex() const { return m_cluster; }

 private:
  Eigen::VectorXi m_cluster;
  std::vector<Eigen::MatrixX3d> m_Q;
  std::vector<Eigen::Matrix3d> m_C0;
  Eigen::MatrixXd m_restTerm;  ///< Σ_g Q_g
};

/// k-means clusters of the rows of `points` (n by d): farthest-point initialisation from row 0, then `iterations`
/// Lloyd steps. Deterministic. Returns the cluster index of each row, in [0, clusters).
/// Cost: O(n·clusters·d) per iteration.
Eigen::VectorXi kMeansClusters(const Eigen::MatrixXd& points, int clusters, int iterations);

}  // namespace sc::spectral
