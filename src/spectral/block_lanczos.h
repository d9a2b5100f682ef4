#pragma once
// Block shift-invert Lanczos: the eigenpairs of S h = λ M h nearest a shift, four right-hand sides at a time.
// Internal to src/spectral (spectrum_slices.cpp runs it in each slice, large_mesh_eigenpairs.cpp once for the whole
// band, repeated_eigenvalues.cpp deflated; lanczos_solver.cpp is the fallback).

#include "spectral/basis_types.h"
#include "spectral/lanczos_block.h"
#include "spectral/shift_invert_operator.h"

namespace sc::spectral::detail {

/// The `pairs` eigenpairs of S h = λ M h whose eigenvalues are nearest σ, sorted ascending, M-orthonormal, by block
/// Lanczos on (S − σM)⁻¹M in the M inner product, without restarts: blocks of kLanczosBlock columns, each made
/// M-orthogonal to the last two blocks (the recurrence) and M-orthonormal by Cholesky QR; against every earlier
/// column (classical Gram–Schmidt as two banded sweeps, each a read of the basis) only as partial re-orthogonalisation
/// decides: in pairs of blocks, as often as the drift each full pass measures asks, so that the basis stays
/// semi-orthogonal (drift ≤ 3·10⁻⁹ < √ε; Simon 1984), the second of a pair only against the leading columns where the
/// first found the drift (reorthogonalisation_schedule.h). The projected block-tridiagonal matrix is solved densely
/// after every block where that costs little beside the block's solves (large meshes), else every few blocks; a Ritz
/// pair (θ, y) counts as converged when ‖(S − σM)⁻¹M y − θ y‖_M ≤ tolerance·max(|θ|, ε^{2/3}) (Spectra's test), which
/// the last block's coupling gives without a solve.
/// Same contract as lanczosNearestPairs() (op factored at σ here unless it already is; cancellation, progress and
/// the solve count through op), except: NotConverged when `maxColumns` (clamped to [pairs + 2·block, #V / 2]) columns
/// are used up first, or when #V is too small for that range; the caller then uses lanczosNearestPairs(), which
/// restarts. The start block is pseudo-random with a fixed seed, so the result is reproducible.
/// `deflation` (M-orthonormal columns X, or nullptr): every vector is kept M-orthogonal to X (removed after each
/// solve), so the pairs returned are those nearest σ among the eigenpairs not in X's span; costs four reads of X per
/// block (repeated_eigenvalues.h finds the missing copies of a repeated eigenvalue this way).
/// Cost: about 2.2·pairs + 55 solves in blocks of four (188 for 60 pairs at 100k); O(#V·K²) GEMM work for K columns
/// (on half to all of the blocks: all at interior shifts, where each solve adds 10⁻¹¹–10⁻¹⁰ of drift);
/// memory #V·maxColumns doubles reserved, of which only the K used are touched.
BasisResult blockLanczosNearestPairs(ShiftInvertOperator& op, const Eigen::VectorXd& mass, int pairs, int maxColumns,
                                     double sigma, const BasisOptions& options,
                                     const Eigen::MatrixXd* deflation = nullptr);

/// The `pairs` eigenpairs nearest σ on op: blockLanczosNearestPairs() with 4·pairs + 40 columns when
/// options.blockLanczos, else or when that does not converge Spectra's lanczosNearestPairs() (ncv = max(5/2·pairs,
/// pairs + 20), restarting) on the same factor. Same contract as lanczosNearestPairs(). `singleVector`, when given, is
/// set to whether Spectra's single-vector run produced the result (it may miss copies of a repeated eigenvalue).
BasisResult nearestPairs(ShiftInvertOperator& op, const Eigen::VectorXd& mass, int pairs, double sigma,
                         const BasisOptions& options, bool* singleVector = nullptr);

}  // namespace sc::spectral::detail
