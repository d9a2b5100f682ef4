#pragma once
// Making eigenvectors of a multi-component mesh live on one component each.

#include <Eigen/Core>

namespace sc::spectral {

/// Rotates the eigenvectors inside every cluster of numerically equal eigenvalues so that each vector is supported
/// on a single connected component, whenever the cluster spans several components.
///
/// Why: on a mesh with identical (or spectrally coincident) components, e.g. two equal spheres, the eigensolver
/// returns arbitrary mixes across components inside each degenerate eigenspace, so moving one component through
/// such a vector would move the other. Also turns the k zero eigenvectors into per-component constants. For an
/// exact invariant subspace, masking a vector to one component gives another eigenvector of the same eigenvalue;
/// per component c the M-Gram matrix of the masked cluster vectors is diagonalised and its unit-eigenvalue
/// directions kept. A cluster whose masked directions do not add up to its size is left unchanged.
/// M-orthonormality is preserved.
/// @param[in] component  #V component label of every vertex, in [0, components).
/// @param[in] mass  #V lumped mass.
/// @param[in] eigenvalues  m eigenvalues, ascending.
/// @param[in,out] H  #V by m M-orthonormal eigenvectors.
/// @param[in] tolerance  eigenvalues within tolerance·max|λ| of their neighbour form a cluster.
/// Cost: O(#V·d²) per multi-component cluster of size d; nothing for a connected mesh.
void localizeToComponents(const Eigen::VectorXi& component, int components, const Eigen::VectorXd& mass,
                          const Eigen::VectorXd& eigenvalues, Eigen::MatrixXd& H, double tolerance = 1e-8);

}  // namespace sc::spectral
