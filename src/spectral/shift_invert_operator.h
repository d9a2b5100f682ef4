#pragma once
// Spectra operator adaptors for the shift-invert generalized eigenproblem S h = λ M h with lumped M.
// Internal to src/spectral (used by lanczos_solver.cpp, spectrum_slices.cpp and the benchmarks).

#include "spectral/laplace_operators.h"
#include "spectral/subtree_ldlt_solve.h"

#include <Eigen/CholmodSupport>

#include <functional>
#include <optional>
#include <span>

namespace sc::spectral::detail {

/// Thrown out of ShiftInvertOperator::perform_op when the observer asks to stop; caught by the caller.
struct SolveCancelled {};

/// CHOLMOD's simplicial LDLᵀ (no pivoting) that also reports the inertia of the factored matrix.
class InertiaLdlt : public Eigen::CholmodSimplicialLDLT<SparseMatrix, Eigen::Lower> {
 public:
  /// The numeric factorisation of `a` (same pattern as analyzePattern()'s) by factorUpLooking() on `threads` threads
  /// (up_looking_ldlt.h: the same factor as factorize(), CHOLMOD's, which remains the fallback for an analysis that
  /// function declines). info() tells whether a pivot was zero.
  void factorizeOnThreads(const SparseMatrix& a, int threads);

  /// Negative entries of D. For A = S − σM this is, by Sylvester's law of inertia, the number of eigenvalues of
  /// S h = λ M h below σ (exact whenever the factorisation succeeded: no zero pivot). Cost: O(#V).
  int negativePivots() const;

  /// Y = A⁻¹X with X's columns split over `threads` threads, each running cholmod_solve2 on the shared factor (read
  /// only) with its own cholmod_common, writing into Y's columns (no solution of CHOLMOD's own to copy: 53 → 42 ms
  /// for four columns at 437k vertices). One solve is bound by the latency of the triangular sweeps' indirect loads
  /// rather than by memory bandwidth, so two threads with two columns each took 0.55–0.6 of one thread's time with
  /// four at 1M vertices. Throws std::runtime_error when CHOLMOD fails (out of memory). Requires factorize().
  void solveColumns(const Eigen::MatrixXd& x, Eigen::MatrixXd& y, int threads) const;

  /// The factor's fill-reducing vertex order: LDLᵀ = P A Pᵀ with (P x)[i] = x[order[i]], #V entries (a
  /// permutation). Requires analyzePattern().
  std::span<const int> order() const;

  /// CHOLMOD's factor, for solvers that read it (SubtreeLdltSolve). Requires factorize().
  const cholmod_factor& factor() const { return *m_cholmodFactor; }

  /// solveColumns() on X and Y in order() (P X and P Y): the two permutations cholmod_solve does otherwise are
  /// gathers and scatters of random rows (a four-column solve at 437k vertices on two threads, the factor on huge
  /// pages: 40.3 against 41.8 ms; 54 against 82 ms without huge pages; docs/benchmarks.md, twelfth pass).
  void solveColumnsInOrder(const Eigen::MatrixXd& x, Eigen::MatrixXd& y, int threads) const;

 private:
  void solveColumns(int system, const Eigen::MatrixXd& x, Eigen::MatrixXd& y, int threads) const;
};

/// y = (S − σM)⁻¹ x through a CHOLMOD simplicial LDLᵀ factor, for any σ that is not an eigenvalue: below the
/// spectrum (σ < 0, S − σM SPD; a negative pivot there means S is not PSD and is reported as a failure) or inside it
/// (spectrum slicing, spectrum_slices.h), where eigenvaluesBelowShift() counts the eigenvalues below σ.
///
/// Simplicial rather than supernodal: on the 100k-vertex dragon (2 cores, OpenBLAS) it factors in 0.18 s vs
/// 0.23 s and, above all, solves in 6.3 ms vs 9–11 ms, because the supernodal solve's many tiny BLAS calls wake
/// OpenBLAS's worker threads each time. The ~250 solves dominate, so this matters (bench/basis_bench.cpp).
/// Spectra holds it by reference: keep it alive while the solver lives. Not copyable (the factor is not).
class ShiftInvertOperator {
 public:
  using Scalar = double;

  /// @param observer  called after every solve with the running count; returns false to cancel.
  ShiftInvertOperator(const SparseMatrix& S, const Eigen::VectorXd& mass, std::function<bool(int)> observer);
  ShiftInvertOperator(const ShiftInvertOperator&) = delete;
  ShiftInvertOperator& operator=(const ShiftInvertOperator&) = delete;

  Eigen::Index rows() const { return m_S.rows(); }
  Eigen::Index cols() const { return m_S.cols(); }

  /// Factorises S − σM (nothing to do when σ is the shift already factored); the symbolic analysis is done once
  /// and reused for later shifts. Throws std::runtime_error when the factorisation fails (a zero pivot), or when
  /// σ < 0 and S − σM is not positive definite (Spectra calls this from its constructor).
  void set_shift(const double& sigma);
  /// y = (S − σM)⁻¹ x. Throws SolveCancelled when the observer returns false.
  void perform_op(const double* x, double* y) const;
  /// Y = (S − σM)⁻¹ X, every column of X at once (CHOLMOD's multi-column solve); counts X.cols() solves. Throws
  /// SolveCancelled when the observer returns false.
  void solve(const Eigen::MatrixXd& x, Eigen::MatrixXd& y) const;
  /// The factor's vertex order (InertiaLdlt::order()): solveInFactorOrder() takes and gives vectors permuted by it,
  /// x̃[i] = x[order[i]]. The same for every shift (the analysis is done once). Requires set_shift().
  std::span<const int> factorOrder() const { return m_factor.order(); }
  /// solve() on X and Y in factorOrder(), without CHOLMOD's two permutations, for a solver that keeps its vectors in
  /// that order throughout (block_lanczos.h): by SubtreeLdltSolve on solveThreads() threads (split on the first
  /// call after a factorisation), or where it cannot read the factor by InertiaLdlt::solveColumnsInOrder(). Not
  /// safe from two threads at once on one operator (that solver's buffers are the operator's; each spectrum slice
  /// has an operator of its own).
  void solveInFactorOrder(const Eigen::MatrixXd& x, Eigen::MatrixXd& y) const;

  int solveCount() const { return m_solves; }
  /// Threads solve() splits its columns over (default 1: spectrum slices already run one slice per core).
  void setSolveThreads(int threads) { m_solveThreads = threads; }
  int solveThreads() const { return m_solveThreads; }
  /// Eigenvalues of S h = λ M h below the factored σ (Sylvester's law of inertia). Requires set_shift().
  int eigenvaluesBelowShift() const { return m_factor.negativePivots(); }

 private:
  const SparseMatrix& m_S;
  const Eigen::VectorXd& m_mass;
  std::function<bool(int)> m_observer;
  InertiaLdlt m_factor;
  bool m_analysed = false;
  bool m_factored = false;
  double m_sigma = 0.0;
  mutable int m_solves = 0;
  int m_solveThreads = 1;
  /// solveInFactorOrder()'s solver for the current factor, split for m_subtreesFor threads (0: not yet tried).
  mutable std::optional<SubtreeLdltSolve> m_subtrees;
  mutable int m_subtreesFor = 0;

  /// Counts `columns` solves, telling the observer after each; throws SolveCancelled when it returns false.
  void countSolves(Eigen::Index columns) const;
};

/// y = M x for the lumped (diagonal) mass matrix; Spectra's B operator and inner product.
class DiagonalMassOperator {
 public:
  using Scalar = double;
  explicit DiagonalMassOperator(const Eigen::VectorXd& mass) : m_mass(mass) {}
  Eigen::Index rows() const { return m_mass.size(); }
  Eigen::Index cols() const { return m_mass.size(); }
  void perform_op(const double* x, double* y) const;

 private:
  const Eigen::VectorXd& m_mass;
};

}  // namespace sc::spectral::detail
