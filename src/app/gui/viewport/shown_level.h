#pragma once
// ShownLevel: the display level a MeshViewport shows and its current frame. It holds the session's shared level
// (spectral::SharedDisplayLevel: K is read in place by both reconstruction paths, never copied) and the frame's Z;
// the rest positions relative to the viewport's origin are the level's (DisplayGeometry::rest, shown through
// ViewportBuffers::rest()).

#include "spectral/display_level.h"

#include <Eigen/Core>

#include <QVector3D>

#include <utility>

namespace sc::app {

class ShownLevel {
 public:
  /// Holds `level` (non-null; its K has #V rows; the viewport's origin is its DisplayGeometry::origin); Z starts at
  /// zero and nothing is shown yet (showing() false). Cost: O(m): the rest box and the bounds of K are the level's
  /// (DisplayGeometry, computed with it off the GUI thread).
  void hold(spectral::SharedDisplayLevel level);
  /// Drops the level (the viewport then shows a plain mesh).
  void clear();

  [[nodiscard]] bool empty() const { return !m_level; }
  [[nodiscard]] const spectral::SharedDisplayLevel& level() const { return m_level; }
  /// n' by m, the shared level's quantised K (needs !empty()).
  [[nodiscard]] const spectral::QuantizedBasis& K() const { return m_level->level.K; }
  [[nodiscard]] int basisSize() const { return m_level ? m_level->basisSize() : 0; }

  /// Shows the frame X̂' + K·Z. @param[in] Z m by 3 (m = basisSize()); an empty Z stands for zero (the rest shape).
  /// Returns false (and changes nothing) for any other shape.
  bool show(const Eigen::MatrixXf& Z);
  /// Whether show(Z) would change nothing: the picture already is X̂' + K·Z (an empty Z: zero). Cost: O(m).
  [[nodiscard]] bool shows(const Eigen::MatrixXf& Z) const;
  /// The current frame's Z, m by 3.
  [[nodiscard]] const Eigen::MatrixXf& Z() const { return m_Z; }
  /// scale ⊙ Z (K().scaled(Z())), m by 3: what the shader multiplies K's int16 entries with.
  [[nodiscard]] const Eigen::MatrixXf& scaledZ() const { return m_scaledZ; }
  /// Whether the picture is X̂' + K·Z (false before the first show() and after explicit positions: stopShowing()).
  [[nodiscard]] bool showing() const { return m_showing; }
  void stopShowing() { m_showing = false; }

  /// Camera bounds of X̂' + K·Z without reconstructing: the rest box widened per coordinate c by the smaller of two
  /// bounds of max_i |(K·Z)_ic|: max_i ‖K_i‖·‖Z_c‖ (Cauchy–Schwarz) and Σ_k max_i |K_ik|·|Z_kc| (Hölder). The second
  /// keeps a few huge rows of K that Z does not use out of the box: a tiny mesh component's constant mode (the 100k
  /// dragon's 3-vertex specks: entries ≈ 17,000 against ≈ 4 on the body) made the first one thousands of times the
  /// shape, and the camera's near plane, a thousandth of that, cut the front of the mesh away. Cost: O(m).
  [[nodiscard]] std::pair<QVector3D, QVector3D> bounds() const;

 private:
  spectral::SharedDisplayLevel m_level;
  Eigen::MatrixXf m_Z;
  Eigen::MatrixXf m_scaledZ;
  bool m_showing = false;
};

}  // namespace sc::app
