#pragma once
// The raw eigensolvers behind manifoldHarmonicBasis(), before localisation and sign fixing.
// Internal to src/spectral (harmonic_basis.cpp, hierarchical_basis.cpp, spectrum_slices.cpp).

#include "spectral/basis_types.h"
#include "spectral/shift_invert_operator.h"

namespace sc::spectral::detail {

/// The first `pairs` eigenpairs of S h = λ M h (ascending, M-orthonormal) by Spectra's shift-invert Lanczos around
/// σ < 0 on a simplicial CHOLMOD factor, into result.basis (eigenvalues, vectors); status and operatorApplications set.
/// @param[in] options  ncv, tolerance, maxRestarts and progress are used (m is not: `pairs` is).
/// Cost: see manifoldHarmonicBasis().
BasisResult lanczosEigenpairs(const LaplaceOperators& ops, int pairs, double sigma, const BasisOptions& options);

/// The `pairs` eigenpairs of S h = λ M h whose eigenvalues are nearest σ (any σ that is not an eigenvalue), by
/// Spectra's shift-invert Lanczos on `op` (factored at σ here unless it already is), sorted ascending, M-orthonormal.
/// @param[in] ncv  Lanczos size, clamped to [pairs + 1, #V]. options: tolerance and maxRestarts are used.
/// Cancellation and progress go through op's observer. operatorApplications is op's solve count afterwards.
BasisResult lanczosNearestPairs(ShiftInvertOperator& op, const Eigen::VectorXd& mass, int pairs, int ncv, double sigma,
                                const BasisOptions& options);

/// Sorts the pairs by ascending eigenvalue, vectors with them (stable; nothing moves when they already are).
/// Cost: O(#V·pairs) copies when any moves.
void sortAscending(HarmonicBasis& basis);

}  // namespace sc::spectral::detail
