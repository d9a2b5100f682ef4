#include "app/gui/viewport/shown_level.h"

#include <utility>

namespace sc::app {

void ShownLevel::hold(spectral::SharedDisplayLevel level) {
  m_level = std::move(level);
  m_Z = Eigen::MatrixXf::Zero(m_level->level.K.cols(), 3);
  m_scaledZ = m_Z;
  m_showing = false;
}

void ShownLevel::clear() {
  m_level.reset();
  m_Z.resize(0, 0);
  m_scaledZ.resize(0, 0);
  m_showing = false;
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
  if (!m_level) {
    return {};
  }
  const spectral::DisplayGeometry& g = m_level->geometry;
  const Eigen::Vector3f cauchySchwarz = g.maxRowNorm * m_Z.colwise().norm().transpose();
  const Eigen::Vector3f hoelder = (g.maxAbsColumn * m_Z.cwiseAbs()).transpose();
  const Eigen::Vector3f reach = cauchySchwarz.cwiseMin(hoelder);
  const Eigen::Vector3f lo = g.lo - reach;
  const Eigen::Vector3f hi = g.hi + reach;
  return {QVector3D(lo.x(), lo.y(), lo.z()), QVector3D(hi.x(), hi.y(), hi.z())};
}

}  // namespace sc::app
