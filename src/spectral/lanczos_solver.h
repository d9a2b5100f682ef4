#pragma once
// The raw eigensolvers behind manifoldHarmonicBasis(), before localisation and sign fixing.
// Internal to src/spectral (harmonic_basis.cpp, hierarchical_basis.cpp).

#include "spectral/basis_types.h"

namespace sc::spectral::detail {

/// The first `pairs` eigenpairs of S h = λ M h (ascending, M-orthonormal) by Spectra's shift-invert Lanczos around
/// σ on a simplicial CHOLMOD factor, into result.basis (eigenvalues, vectors); status and operatorApplications set.
/// @param[in] options  ncv, tolerance, maxRestarts and progress are used (m is not: `pairs` is).
/// Cost: see manifoldHarmonicBasis().
BasisResult lanczosEigenpairs(const LaplaceOperators& ops, int pairs, double sigma, const BasisOptions& options);

}  // namespace sc::spectral::detail
