#pragma once
// Spectrum slicing: the first m eigenpairs of S h = λ M h as a few shift-invert Lanczos runs around shifts spread
// over the wanted band, run on parallel threads, each placed exactly in the spectrum by the inertia of its own LDLᵀ
// factor (Sylvester's law). Vallet & Lévy (2008) compute manifold harmonics band by band the same way.
// Internal to src/spectral (harmonic_basis.cpp dispatches to it for BasisSolver::Slices).

#include "spectral/basis_types.h"

#include <string>
#include <vector>

namespace sc::spectral::detail {

/// Eigenpairs nearest one shift, with their exact positions in the ascending spectrum.
struct SpectrumSlice {
  double shift{};
  int first{};                  ///< index of eigenvalues[0] in the ascending spectrum (0 = the smallest)
  Eigen::VectorXd eigenvalues;  ///< ascending, at indices first, first + 1, …
  Eigen::MatrixXd vectors;      ///< #V by eigenvalues.size(), M-orthonormal
  int last() const { return first + static_cast<int>(eigenvalues.size()) - 1; }
};

/// Indices [0, m) assembled from slices, or why they cannot be.
struct MergedSlices {
  Eigen::VectorXd eigenvalues;  ///< m, ascending
  Eigen::MatrixXd vectors;      ///< #V by m
  std::vector<int> handOvers;   ///< the first index taken from each slice after the first that contributes
  std::string error;            ///< empty on success
};

/// Assembles the indices [0, m) from slices given in any order; a slice inside another is ignored.
/// Where two slices overlap, every index of the overlap must carry the same eigenvalue in both, within
/// agreement·(|λ| + scale): a run that missed an eigenvalue has all its indices on one side shifted, which this
/// catches. The hand-over index s is the one after the largest relative gap (λ_s − λ_{s−1})/(|λ_s| + scale) of the
/// overlap, which must be at least minimumGap: a hand-over inside a cluster would mix vectors of one eigenspace from
/// two runs, which are not orthogonal. error names the failed check (coverage, agreement or gap).
/// Cost: O(#V·m) copies plus O(overlaps).
MergedSlices mergeSlices(std::vector<SpectrumSlice> slices, int m, double scale, double agreement, double minimumGap);

/// The first options.m eigenpairs of S h = λ M h (ascending, M-orthonormal) by spectrum slicing, into result.basis,
/// before localisation and sign fixing; result.solver is Slices, or Lanczos where it fell back to it.
///
/// 1. k slices (options.slices; 0: one per hardware thread, at least 2, at most m/12) own consecutive index windows of
/// [0, m) that overlap
///    by a guard of max(3, m/(10k)) indices. Slice 0 is shifted to σ < 0 (its window is the bottom of the spectrum);
///    slice j > 0 to the eigenvalue Weyl's law predicts at its window's centre, λ ≈ (index − components)·4π/area.
/// 2. Each slice, on one of min(k, hardware threads) threads: LDLᵀ of S − σ_j M, whose negative pivots count the
///    eigenvalues below σ_j exactly; from that count, how many pairs nearest σ_j cover its window; block Lanczos
///    for them (block_lanczos.h; Spectra's restarted Lanczos with ncv = 5/2 of that when options.blockLanczos is
///    false or the block run does not converge in 4 columns per pair), asked again (at most twice, same factor) for
///    twice the shortfall when the spectrum's uneven density leaves an end of the window uncovered. The count places
///    every pair it returns at its index.
/// 3. Checks: Sylvester's count at a gap just above index m − 1 (one more factorisation: the top slice's part above
///    its own shift is the only one no overlap checks), mergeSlices(), and the M-orthonormality of the columns around
///    each hand-over (≤ 1e-8). Every index is thus placed by an exact count and checked by a second one.
/// Runs blockLanczosEigenpairs() (large_mesh_eigenpairs.h) instead above options.sliceMaximumVertices (one factor and
/// one Krylov basis in memory; lanczosEigenpairs() when options.blockLanczos is false), and lanczosEigenpairs() when #V
/// is below options.sliceMinimumVertices or k < 2; falls back to hierarchicalEigenpairs() when a check of step 3 fails
/// (result.message says which). Cost: k + 1 simplicial factorisations (k symbolic analyses), about 3.5·(m + 2·guard·k)
/// solves in blocks of four and O(#V·Σ K_j²) orthogonalisation for K_j ≈ 3.5·m/k Krylov columns (against O(#V·(5m/2)²)
/// for one run), spread over the threads; memory O(threads·(nnz(L) + #V·K_j) + #V·m).
BasisResult slicedEigenpairs(const LaplaceOperators& ops, double sigma, const BasisOptions& options);

}  // namespace sc::spectral::detail
