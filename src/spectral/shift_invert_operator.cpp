#include "spectral/shift_invert_operator.h"

#include <stdexcept>
#include <utility>

namespace sc::spectral::detail {

ShiftInvertOperator::ShiftInvertOperator(const SparseMatrix& S, const Eigen::VectorXd& mass,
                                         std::function<bool(int)> observer)
    : m_S(S), m_mass(mass), m_observer(std::move(observer)) {}

void ShiftInvertOperator::set_shift(const double& sigma) {
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
    throw std::runtime_error("Cholesky factorisation of S - sigma*M failed (S not PSD or M singular)");
}

void ShiftInvertOperator::perform_op(const double* x, double* y) const {
  Eigen::Map<Eigen::VectorXd>(y, rows()) = m_factor.solve(Eigen::Map<const Eigen::VectorXd>(x, rows()));
  ++m_solves;
  if (m_observer && !m_observer(m_solves)) throw SolveCancelled{};
}

void DiagonalMassOperator::perform_op(const double* x, double* y) const {
  Eigen::Map<Eigen::VectorXd>(y, rows()) = m_mass.cwiseProduct(Eigen::Map<const Eigen::VectorXd>(x, rows()));
}

}  // namespace sc::spectral::detail
