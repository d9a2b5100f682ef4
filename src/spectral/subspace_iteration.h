#pragma once
// Block shift-invert subspace iteration with Rayleigh–Ritz and locking for S h = λ M h (lumped M).
// Internal to src/spectral: manifoldHarmonicBasis() calls it with a start block prolonged from a coarse level.

#include "spectral/laplace_operators.h"

#include <functional>

namespace sc::spectral::detail {

/// Settings of subspaceIteration().
struct SubspaceIterationOptions {
  int wanted = 100;               ///< m: the eigenpairs wanted (the start block has more columns: guard vectors).
  double tolerance = 1e-6;        ///< on relativeResidual() of every wanted pair.
  int maxSweeps = 200;            ///< sweeps (solve, Rayleigh–Ritz) before giving up.
  double maxGramCondition = 1e8;  ///< bounds the solves per sweep (see subspaceIteration()).
  int threads = 0;                ///< threads solving column chunks at once; 0: the hardware's concurrency, at most 4.
  /// Called with the estimated fraction done in [0, 1] after each sweep; return false to cancel.
  std::function<bool(double fraction)> progress;
};

/// How subspaceIteration() ended and what it found.
struct SubspaceIterationResult {
  enum class Status { Converged, NotConverged, FactorizationFailed, Cancelled } status = Status::NotConverged;
  Eigen::VectorXd eigenvalues;  ///< m ascending Ritz values.
  Eigen::MatrixXd vectors;      ///< #V by m, M-orthonormal Ritz vectors.
  Eigen::VectorXd residuals;    ///< m relative residuals (relativeResidual()).
  /// #V by b − m: the unlocked Ritz vectors of the last sweep (the next pairs, unconverged), for starting a finer
  /// level with the full block width.
  Eigen::MatrixXd guard;
  int sweeps{};  ///< Rayleigh–Ritz steps done.
  int solves{};  ///< right-hand sides solved with the factor (columns, not blocks).
};

/// The relative residual of an M-normalised pair (θ, x): ‖Sx − θMx‖_{M⁻¹} / (|θ| + |σ|).
///
/// Why this norm: for S x = λ M x the M⁻¹-norm of the residual is the one the classical bounds use (Parlett):
/// the nearest eigenvalue λ satisfies |θ − λ| ≤ ‖r‖_{M⁻¹} and |θ − λ| ≤ ‖r‖²_{M⁻¹}/δ, and the angle (in the M-inner
/// product) between x and the eigenspace is at most ‖r‖_{M⁻¹}/δ, with δ the gap to the rest of the spectrum.
/// Dividing by |θ| + |σ| (σ < 0 the shift, about the first non-zero eigenvalue of a sphere of the same area)
/// makes it scale-free (S is invariant under scaling a surface, M and λ scale as length², 1/length²) and keeps it
/// meaningful for the zero eigenvalues, where ‖Sx‖ itself is only round-off.
/// @param[in] Sx, Mx  #V by k blocks S·X and M·X of M-orthonormal columns; @param[in] theta  k Ritz values.
/// Cost: O(#V·k).
Eigen::VectorXd relativeResiduals(const Eigen::MatrixXd& Sx, const Eigen::MatrixXd& Mx, const Eigen::VectorXd& mass,
                                  const Eigen::VectorXd& theta, double sigma);

/// The `wanted` smallest eigenpairs of S h = λ M h by subspace iteration with the operator A = (S − σM)⁻¹M.
///
/// Each sweep applies A d times to the active block with one simplicial CHOLMOD factor of S − σM (chunks of 4
/// right-hand sides per sweep over the factor, the chunks spread over options.threads threads), M-orthogonalises it
/// against the locked pairs, and does Rayleigh–Ritz (the small generalized problem YᵀSY w = θ YᵀMY w). Leading pairs
/// whose relativeResiduals() is below the tolerance are locked and leave the active block, which then shrinks while its
/// top index stays at the start block's width b: the guard vectors b − m set the convergence rate (|λ_i − σ| / |λ_{b+1}
/// − σ| per application for pair i). d is the largest count (≤ 4) for which the Gram matrix of the filtered block stays
/// below maxGramCondition, estimated from the Ritz values ((θ_top − σ)/(θ_low − σ))^{2d}. A final Rayleigh–Ritz on the
/// m locked vectors makes them M-orthonormal to round-off.
/// @param[in] ops  S (#V by #V, PSD) and lumped mass (> 0).
/// @param[in] sigma  shift < 0 (S − σM SPD).
/// @param[in] start  #V by b start block, b > wanted (e.g. coarse eigenvectors prolonged to the fine mesh).
/// Cost: one sparse Cholesky, then per sweep d·a triangular solve pairs (a = active columns) and O(#V·a·(a + l))
/// dense work (BLAS-3, in buffers allocated once); memory O(nnz(L) + 4·#V·b + #V·m).
SubspaceIterationResult subspaceIteration(const LaplaceOperators& ops, double sigma, Eigen::MatrixXd start,
                                          const SubspaceIterationOptions& options);

}  // namespace sc::spectral::detail
