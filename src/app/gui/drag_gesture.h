#pragma once
// The handle-drag gesture of the viewport: mouse motion → a rigid pose of the handle group. Pure: no GL, no
// widget; the camera is a frozen snapshot of OrbitCamera's matrices taken when the drag starts.

#include <Eigen/Core>

#include <QMatrix4x4>
#include <QPointF>
#include <QSizeF>

namespace sc::app {

/// World-space vector that moves `point` by `deltaPixels` on screen while keeping its depth, i.e. a translation
/// in the view plane through `point` (exact under perspective: unprojects the shifted point at the same NDC
/// depth). Its length grows linearly with |deltaPixels| and with the point's distance from the eye.
/// @param[in] viewport     widget size in the same pixel units as deltaPixels (y down, as in Qt).
/// @return zero if point lies behind the eye or the matrices are singular.
[[nodiscard]] Eigen::Vector3d viewPlaneDelta(const QMatrix4x4& view, const QMatrix4x4& projection, QSizeF viewport,
                                             const Eigen::Vector3d& point, QPointF deltaPixels);

/// Accumulates a drag into the pose a HandleTransform needs: x ↦ R·(x − c) + c + t, with c the handle centroid
/// at the start of the drag, R = rotation() and t = translation().
///
/// Each moveTo() adds one segment from the previous mouse position:
/// - translate: t += viewPlaneDelta(…) at the current centroid c + t;
/// - rotate: R ← Rz(θ)·R, a rotation about the view axis (towards the viewer) through the current centroid, θ the
///   signed angle the cursor swept around the centroid's screen projection (counter-clockwise on screen is
///   positive, so the shape follows the cursor).
/// Rotating about the moved centroid leaves t unchanged, so segments of both kinds compose into one (R, t).
class DragGesture {
 public:
  /// @param[in] centroid  handle centroid in the space `view` maps from.
  /// @param[in] start     mouse position where the drag began (widget pixels, y down).
  DragGesture(const QMatrix4x4& view, const QMatrix4x4& projection, QSizeF viewport, const Eigen::Vector3d& centroid,
              QPointF start);

  /// Extends the drag to `pos`; rotate selects the segment's kind (e.g. Ctrl held).
  void moveTo(QPointF pos, bool rotate);

  [[nodiscard]] const Eigen::Vector3d& translation() const { return m_translation; }
  [[nodiscard]] const Eigen::Matrix3d& rotation() const { return m_rotation; }

 private:
  [[nodiscard]] QPointF toScreen(const Eigen::Vector3d& point) const;

  QMatrix4x4 m_view;
  QMatrix4x4 m_projection;
  QSizeF m_viewport;
  Eigen::Vector3d m_centroid;
  QPointF m_last;
  Eigen::Vector3d m_translation = Eigen::Vector3d::Zero();
  Eigen::Matrix3d m_rotation = Eigen::Matrix3d::Identity();
};

}  // namespace sc::app
