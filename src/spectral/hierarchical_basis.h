#pragma once
// The hierarchical eigensolver: coarse eigenvectors of an aggregated level as the start of fine subspace iterations.
// Internal to src/spectral (harmonic_basis.cpp dispatches to it for BasisSolver::Hierarchical).

#include "spectral/basis_types.h"

namespace sc::spectral::detail {

/// The first options.m eigenpairs of S h = λ M h (ascending, M-orthonormal, residuals ≤ options.residualTolerance)
/// into result.basis, before localisation and sign fixing.
///
/// 1. b = m + guard columns; aggregateOperators() coarsens (S, M) to ≥ 8b vertices (a Galerkin level, P piecewise
///    constant); when no pass can coarsen, the plain Lanczos solver runs instead (result.solver says so).
/// 2. Lanczos (tolerance 1e-6) gives the b smallest coarse eigenvectors; P prolongs them to the fine mesh.
/// 3. subspaceIteration() on the fine mesh around the same σ, until every wanted pair's residual is below tolerance.
/// Cost: aggregation O(nnz(S)), the coarse Lanczos (small), one supernodal Cholesky of S − σM and a few sweeps of
/// block solves plus O(#V·b²) dense work; memory O(nnz(L) + about 5·#V·b doubles).
BasisResult hierarchicalEigenpairs(const LaplaceOperators& ops, double sigma, const BasisOptions& options);

}  // namespace sc::spectral::detail
