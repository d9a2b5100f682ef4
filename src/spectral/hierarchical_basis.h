#pragma once
// The hierarchical eigensolver: coarse eigenvectors of an aggregated level as the start of fine subspace iterations.
// Internal to src/spectral (harmonic_basis.cpp dispatches to it for BasisSolver::Hierarchical).

#include "spectral/basis_types.h"

namespace sc::spectral::detail {

/// The first options.m eigenpairs of S h = λ M h (ascending, M-orthonormal, residuals ≤ options.residualTolerance)
/// into result.basis, before localisation and sign fixing.
///
/// 1. b = m + guard columns; aggregationHierarchy() coarsens (S, M) level by level (smoothed aggregation, Galerkin)
///    while a level keeps ≥ 2b vertices; when no step can, the plain Lanczos solver runs instead (result.solver
///    says so).
/// 2. Lanczos (tolerance 1e-6) gives the b smallest eigenvectors of the coarsest level.
/// 3. Level by level towards the mesh: prolong the block through the level's smoothed P and run subspaceIteration()
///    on it (tolerance 1e-3 on intermediate levels: only a start), until every wanted pair of the mesh itself has a
///    residual below options.residualTolerance. result.sweeps counts the mesh's sweeps; operatorApplications all
///    right-hand sides solved on every level.
/// Cost: aggregation O(nnz(S)) per level, the coarse Lanczos (small), per level one simplicial Cholesky of S − σM and
/// a few sweeps of block solves plus O(#V·b²) dense work; memory O(nnz(L) + about 7·#V·b doubles) on the mesh.
BasisResult hierarchicalEigenpairs(const LaplaceOperators& ops, double sigma, const BasisOptions& options);

}  // namespace sc::spectral::detail
