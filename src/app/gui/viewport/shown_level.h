#pragma once
// ShownLevel: the display level a MeshViewport shows and its current frame. It holds the session's shared level
// (spectral::SharedDisplayLevel: K is read in place by both reconstruction paths, never copied) and the frame's Z;
// the rest positions relative to the viewport's origin live in ViewportBuffers::rest().

#include "spectral/display_level.h"

#include <Eigen/Core>

#include <QVector3D>

#include <span>
#include <utility>

namespace sc::app {

class ShownLevel {
 public:
  /// Holds `level` (non-null; its K has #V rows); Z starts at zero and nothing is shown yet (showing() false).
  /// `rest`: 3·n' rest positions relative to the viewport's origin (for the camera bounds). Cost: O(n'·m) once
  /// (max_i ‖K_i‖).
  void hold(spectral::SharedDisplayLevel level, std::span<const float> rest);
  /// Drops the level (the viewport then shows a plain mesh).
  void clear();

  [[nodiscard]] bool empty() const { return !m_level; }
  [[nodiscard]] const spectral::SharedDisplayLevel& level() const { return m_level; }
  /// n' by m, the shared level's K (needs !empty()).
  [[nodiscard]] const spectral::RowMatrixXf& K() const { return m_level->level.K; }
  [[nodiscard]] int basisSize() const { return m_level ? m_level->basisSize() : 0; }

  /// Shows the frame X̂' + K·Z. @param[in] Z m by 3 (m = basisSize()); an empty Z stands for zero (the rest shape).
  /// Returns false (and changes nothing) for any other shape.
  bool show(const Eigen::MatrixXf& Z);
  /// The current frame's Z, m by 3.
  [[nodiscard]] const Eigen::MatrixXf& Z() const { return m_Z; }
  /// Whether the picture is X̂' + K·Z (false before the first show() and after explicit positions: stopShowing()).
  [[nodiscard]] bool showing() const { return m_showing; }
  void stopShowing() { m_showing = false; }

  /// Camera bounds of X̂' + K·Z without reconstructing: the rest box widened by max_i ‖K_i‖·‖Z_c‖ ≥ |(K·Z)_ic| per
  /// coordinate (Cauchy–Schwarz). Cost: O(m).
  [[nodiscard]] std::pair<QVector3D, QVector3D> bounds() const;

 private:
  spectral::SharedDisplayLevel m_level;
  Eigen::MatrixXf m_Z;
  bool m_showing = false;
  float m_maxRowNorm = 0.0f;
  Eigen::Vector3f m_restLo = Eigen::Vector3f::Zero();
  Eigen::Vector3f m_restHi = Eigen::Vector3f::Zero();
};

}  // namespace sc::app
