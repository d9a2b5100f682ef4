#include "app/gui/viewport/shown_level.h"

#include <algorithm>
#include <utility>

namespace sc::app {

void ShownLevel::hold(spectral::SharedDisplayLevel level, std::span<const float> rest) {
  m_level = std::move(level);
  const spectral::QuantizedBasis& K = m_level->level.K;
  m_maxRowNorm = 0.0f;
  m_maxAbsColumn = Eigen::RowVectorXf::Zero(K.cols());
  for (Eigen::Index i = 0; i < K.rows(); ++i) {
    const Eigen::RowVectorXf row = K.row(i);
    m_maxRowNorm = std::max(m_maxRowNorm, row.norm());
    m_maxAbsColumn = m_maxAbsColumn.cwiseMax(row.cwiseAbs());
  }
  Eigen::Map<const Eigen::Matrix<float, Eigen::Dynamic, 3, Eigen::RowMajor>> R(
      rest.data(), static_cast<Eigen::Index>(rest.size() / 3), 3);
  m_restLo = R.rows() > 0 ? Eigen::Vector3f(R.colwise().minCoeff().transpose()) : Eigen::Vector3f::Zero();
  m_restHi = R.rows() > 0 ? Eigen::Vector3f(R.colwise().maxCoeff().transpose()) : Eigen::Vector3f::Zero();
  m_Z = Eigen::MatrixXf::Zero(K.cols(), 3);
  m_scaledZ = m_Z;
  m_showing = false;
}

void ShownLevel::clear() {
  m_level.reset();
  m_Z.resize(0, 0);
  m_scaledZ.resize(0, 0);
  m_showing = false;
  m_maxRowNorm = 0.0f;
  m_maxAbsColumn.resize(0);
}

bool ShownLevel::show(const Eigen::MatrixXf& Z) {
  if (!m_level) {
    return false;
  }
  if (Z.size() == 0) {
    m_Z.setZero();
  } else if (Z.rows() == m_Z.rows() && Z.cols() == 3) {
    m_Z = Z;
  } else {
    return false;
  }
  m_scaledZ = m_level->level.K.scaled(m_Z);
  m_showing = true;
  return true;
}

bool ShownLevel::shows(const Eigen::MatrixXf& Z) const {
  if (!m_level || !m_showing) {
    return false;
  }
  if (Z.size() == 0) {
    return m_Z.isZero(0.0f);
  }
  return Z.rows() == m_Z.rows() && Z.cols() == m_Z.cols() && Z == m_Z;
}

std::pair<QVector3D, QVector3D> ShownLevel::bounds() const {
  const Eigen::Vector3f cauchySchwarz = m_maxRowNorm * m_Z.colwise().norm().transpose();
  const Eigen::Vector3f hoelder = (m_maxAbsColumn * m_Z.cwiseAbs()).transpose();
  const Eigen::Vector3f reach = cauchySchwarz.cwiseMin(hoelder);
  const Eigen::Vector3f lo = m_restLo - reach;
  const Eigen::Vector3f hi = m_restHi + reach;
  return {QVector3D(lo.x(), lo.y(), lo.z()), QVector3D(hi.x(), hi.y(), hi.z())};
}

}  // namespace sc::app
