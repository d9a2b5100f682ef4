#pragma once
// Block shift-invert Lanczos: the eigenpairs of S h = λ M h nearest a shift, four right-hand sides at a time.
// Internal to src/spectral (spectrum_slices.cpp runs it in each slice; lanczos_solver.cpp falls back to Spectra).

#include "spectral/basis_types.h"
#include "spectral/shift_invert_operator.h"

namespace sc::spectral::detail {

/// Right-hand sides per block: CHOLMOD's simplicial solve unrolls up to four columns, which measured 3.3 ms per
/// right-hand side against 6.4 ms for one at a time on the 100k dragon.
inline constexpr int kLanczosBlock = 4;

/// The `pairs` eigenpairs of S h = λ M h whose eigenvalues are nearest σ, sorted ascending, M-orthonormal, by block
/// Lanczos on (S − σM)⁻¹M in the M inner product, without restarts: blocks of kLanczosBlock columns, each made
/// M-orthogonal to the last two blocks (the recurrence) and M-orthonormal by Cholesky QR; against every earlier
/// column (classical Gram–Schmidt as two GEMMs, each a read of the basis) only as partial re-orthogonalisation
/// decides: in pairs of blocks, as often as the drift each full pass measures asks, so that the basis stays
/// semi-orthogonal (drift ≤ 10⁻⁹ < √ε; Simon 1984). The projected block-tridiagonal matrix is solved densely after
/// every block where that costs little beside the block's solves (large meshes), else every few blocks; a Ritz
/// pair (θ, y) counts as converged when ‖(S − σM)⁻¹M y − θ y‖_M ≤ tolerance·max(|θ|, ε^{2/3}) (Spectra's test), which
/// the last block's coupling gives without a solve.
/// Same contract as lanczosNearestPairs() (op factored at σ here unless it already is; cancellation, progress and
/// the solve count through op), except: NotConverged when `maxColumns` (clamped to [pairs + 2·block, #V / 2]) columns
/// are used up first, or when #V is too small for that range; the caller then uses lanczosNearestPairs(), which
/// restarts. The start block is pseudo-random with a fixed seed, so the result is reproducible.
/// Cost: about 2.2·pairs + 55 solves in blocks of four (188 for 60 pairs at 100k); O(#V·K²) GEMM work for K columns
/// (on half to all of the blocks: all at interior shifts, where each solve adds 10⁻¹¹–10⁻¹⁰ of drift);
/// memory #V·maxColumns doubles reserved, of which only the K used are touched.
BasisResult blockLanczosNearestPairs(ShiftInvertOperator& op, const Eigen::VectorXd& mass, int pairs, int maxColumns,
                                     double sigma, const BasisOptions& options);

/// The `pairs` eigenpairs nearest σ on op: blockLanczosNearestPairs() with 4·pairs + 40 columns when
/// options.blockLanczos, else or when that does not converge Spectra's lanczosNearestPairs() (ncv = max(5/2·pairs,
/// pairs + 20), restarting) on the same factor. Same contract as lanczosNearestPairs().
BasisResult nearestPairs(ShiftInvertOperator& op, const Eigen::VectorXd& mass, int pairs, double sigma,
                         const BasisOptions& options);

/// The first `pairs` eigenpairs around σ < 0 by nearestPairs() on a new factor; progress and cancellation through
/// options.progress. For meshes too large for spectrum slicing's several factors and bases. Runs on one thread per
/// core of its own (the solves' columns, the sweeps' bands of rows, the Ritz vectors' bands), with OpenBLAS on one
/// thread meanwhile (single_threaded_blas.h).
/// Cost: one factorisation, about 3.2·pairs solves, O(#V·K²) GEMM work; memory nnz(L) + #V·K doubles, K ≈ 3.2·pairs.
BasisResult blockLanczosEigenpairs(const LaplaceOperators& ops, int pairs, double sigma, const BasisOptions& options);

}  // namespace sc::spectral::detail
