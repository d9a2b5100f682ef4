#pragma once
// The eigensolver of meshes too large for spectrum slicing: one block Lanczos run, its missing copies of repeated
// eigenvalues completed. Internal to src/spectral (spectrum_slices.cpp dispatches to it).

#include "spectral/basis_types.h"

namespace sc::spectral::detail {

/// The first `pairs` eigenpairs around σ < 0 by nearestPairs() (block_lanczos.h) on a new factor, to
/// options.largeMeshTolerance rather than options.tolerance, then
/// completeRepeatedEigenvalues() (repeated_eigenvalues.h); progress and cancellation through options.progress. For
/// meshes too large for spectrum slicing's several factors and bases. Runs on one thread per core of its own (the
/// solves' columns, the sweeps' bands of rows, the Ritz vectors' bands), with OpenBLAS on one thread meanwhile
/// (single_threaded_blas.h).
/// Cost: one factorisation, about 2.2·pairs + 55 solves (K columns), O(#V·K²) sweep work; memory nnz(L) + #V·K
/// doubles (a cluster of kLanczosBlock or more equal eigenvalues adds factorisations and small runs, e.g. a mesh of
/// four or more components: its zeros).
BasisResult blockLanczosEigenpairs(const LaplaceOperators& ops, int pairs, double sigma, const BasisOptions& options);

}  // namespace sc::spectral::detail
