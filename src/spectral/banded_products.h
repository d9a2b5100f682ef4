#pragma once
// Products of a tall matrix Q (#V × k) with a thin block W (#V × b, b a handful of columns) in the M inner product,
// each done in one sweep over bands of rows, so that W's band and the small results stay in cache: the block
// Lanczos steps' local orthogonalisation and Cholesky QR. Internal to src/spectral.
//
// Written as separate GEMMs with #V × b temporaries, those two steps took 8.9 s of the 1M-vertex basis (77 blocks);
// as these sweeps, 2.5 s (temporary timers, one run each). The sums over bands are taken per thread chunk and added
// in chunk order, so a result depends on `threads` but not on scheduling.

#include <Eigen/Core>

namespace sc::spectral::detail {

/// Qᵀ·diag(mass)·W (k × b). Cost: one read of Q and W, 2·#V·k·b flops.
Eigen::MatrixXd massProjection(const Eigen::Ref<const Eigen::MatrixXd>& q, const Eigen::VectorXd& mass,
                               const Eigen::MatrixXd& w, int threads);

/// W −= Q·H, and returns the new W's Gram matrix Wᵀ·diag(mass)·W (b × b). Cost: one read of Q, one read and write
/// of W, 2·#V·b·(k + b) flops.
Eigen::MatrixXd subtractWithGram(Eigen::MatrixXd& w, const Eigen::Ref<const Eigen::MatrixXd>& q,
                                 const Eigen::MatrixXd& h, const Eigen::VectorXd& mass, int threads);

/// What subtractWithGramAndProjection() leaves: the new W's Gram matrix Wᵀ·diag(mass)·W (b × b) and its projection
/// Qᵀ·diag(mass)·W (k × b).
struct SubtractedBlock {
  Eigen::MatrixXd gram;
  Eigen::MatrixXd projection;
};

/// subtractWithGram() that also returns the new W's projection on Q, taken from each band while it is in cache:
/// the second pass of a classical Gram–Schmidt against a few columns then needs no sweep of its own to measure what
/// the first left. For k of a handful of columns (Q's band stays in cache). Cost: one read of Q, one read and write
/// of W, 2·#V·b·(2k + b) flops.
SubtractedBlock subtractWithGramAndProjection(Eigen::MatrixXd& w, const Eigen::Ref<const Eigen::MatrixXd>& q,
                                              const Eigen::MatrixXd& h, const Eigen::VectorXd& mass, int threads);

/// W ← W·R for R of b × b, and returns the new W's Gram matrix (b × b). Cost: one read and write of W.
Eigen::MatrixXd multiplyWithGram(Eigen::MatrixXd& w, const Eigen::MatrixXd& r, const Eigen::VectorXd& mass,
                                 int threads);

/// Out = W·R and Weighted = diag(mass)·Out in one sweep, W untouched (Out and Weighted #V × b, sized by the caller):
/// the last Cholesky QR pass of a block written straight into the Krylov basis, with the next solve's right-hand
/// sides. Cost: one read of W, two writes.
void multiplyInto(const Eigen::MatrixXd& w, const Eigen::MatrixXd& r, const Eigen::VectorXd& mass,
                  Eigen::Ref<Eigen::MatrixXd> out, Eigen::MatrixXd& weighted, int threads);

/// Wᵀ·diag(mass)·W (b × b). Cost: one read of W.
Eigen::MatrixXd massGram(const Eigen::MatrixXd& w, const Eigen::VectorXd& mass, int threads);

}  // namespace sc::spectral::detail
