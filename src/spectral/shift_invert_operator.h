#pragma once
// Spectra operator adaptors for the shift-invert generalized eigenproblem S h = λ M h with lumped M.
// Internal to src/spectral (used by harmonic_basis.cpp and the benchmarks).

#include "spectral/laplace_operators.h"

#include <Eigen/CholmodSupport>

#include <functional>

namespace sc::spectral::detail {

/// Thrown out of ShiftInvertOperator::perform_op when the observer asks to stop; caught by the caller.
struct SolveCancelled {};

/// y = (S − σM)⁻¹ x through a CHOLMOD simplicial Cholesky factor LLᵀ (valid for σ < λ_min, i.e. σ < 0 here).
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

  /// Factorises S − σM; the symbolic analysis is done once and reused for later shifts.
  /// Throws std::runtime_error when the factorisation fails (Spectra calls this from its constructor).
  void set_shift(const double& sigma);
  /// y = (S − σM)⁻¹ x. Throws SolveCancelled when the observer returns false.
  void perform_op(const double* x, double* y) const;

  int solveCount() const { return m_solves; }

 private:
  const SparseMatrix& m_S;
  const Eigen::VectorXd& m_mass;
  std::function<bool(int)> m_observer;
  Eigen::CholmodSimplicialLLT<SparseMatrix, Eigen::Lower> m_factor;
  bool m_analysed = false;
  mutable int m_solves = 0;
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
