#include "spectral/shift_invert_operator.h"

#include <stdexcept>
#include <utility>

namespace sc::spectral::detail {

int InertiaLdlt::negativePivots() const {
  // A simplicial LDLᵀ factor keeps D on L's diagonal: the first entry of each column (cholmod_factor, is_ll false).
  const cholmod_factor& factor = *m_cholmodFactor;
  const auto* values = static_cast<const double*>(factor.x);
  const auto* columnStarts = static_cast<const int*>(factor.p);
  int negatives = 0;
  for (std::size_t column = 0; column < factor.n; ++column) negatives += values[columnStarts[column]] < 0.0 ? 1 : 0;
  return negatives;
}

ShiftInvertOperator::ShiftInvertOperator(const SparseMatrix& S, const Eigen::VectorXd& mass,
                                         std::function<bool(int)> observer)
    : m_S(S), m_mass(mass), m_observer(std::move(observer)) {}

void ShiftInvertOperator::set_shift(const double& sigma) {
  if (m_factored && sigma == m_sigma) return;
  m_factored = false;
  SparseMatrix shiftedMass(m_S.rows(), m_S.cols());
  shiftedMass.setIdentity();
  shiftedMass.diagonal() = -sigma * m_mass;
  const SparseMatrix shifted = m_S + shiftedMass;
  if (!m_analysed) {
    m_factor.analyzePattern(shifted);
    m_analysed = true;
  }
  m_factor.factorize(shifted);
  if (m_factor.info() != Eigen::Success)
    throw std::runtime_error("LDL' factorisation of S - sigma*M failed (a zero pivot: sigma is an eigenvalue)");
  if (sigma < 0.0 && m_factor.negativePivots() > 0)
    throw std::runtime_error("S - sigma*M is not positive definite for sigma < 0 (S not PSD or M singular)");
  m_sigma = sigma;
  m_factored = true;
}

void ShiftInvertOperator::perform_op(const double* x, double* y) const {
  Eigen::Map<Eigen::VectorXd>(y, rows()) = m_factor.solve(Eigen::Map<const Eigen::VectorXd>(x, rows()));
  ++m_solves;
  if (m_observer && !m_observer(m_solves)) throw SolveCancelled{};
}

void ShiftInvertOperator::solve(const Eigen::MatrixXd& x, Eigen::MatrixXd& y) const {
  y = m_factor.solve(x);
  for (Eigen::Index column = 0; column < x.cols(); ++column) {
    ++m_solves;
    if (m_observer && !m_observer(m_solves)) throw SolveCancelled{};
  }
}

void DiagonalMassOperator::perform_op(const double* x, double* y) const {
  Eigen::Map<Eigen::VectorXd>(y, rows()) = m_mass.cwiseProduct(Eigen::Map<const Eigen::VectorXd>(x, rows()));
}

}  // namespace sc::spectral::detail
