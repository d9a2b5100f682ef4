#pragma once
// A turntable camera around a target point: the view math behind MeshViewport, free of any GL or widget.

#include <QMatrix4x4>
#include <QVector3D>

#include <span>
#include <vector>

namespace sc::app {

/// Turntable orbit camera with a y-up world. The eye sits on a sphere of radius distance() around target(), at
/// angles yaw (about +y, degrees) and pitch (elevation, degrees, clamped to ±89). Projection is perspective with a
/// fixed vertical field of view.
///
/// Framing contract: frame() centres and fits a point set (a mesh's vertices) so that, in perspective, its
/// extreme points sit symmetrically at kFillFraction of the half-view on the tighter axis. Until the user orbits,
/// pans or zooms, the fit is redone whenever the viewport size changes, so a mesh framed before its widget is
/// shown is still framed for the final size.
class OrbitCamera {
 public:
  static constexpr float kFieldOfViewY = 30.0f;          ///< vertical field of view, degrees.
  static constexpr float kDefaultYaw = -35.0f;           ///< initial yaw after frame(), degrees.
  static constexpr float kDefaultPitch = 18.0f;          ///< initial elevation after frame(), degrees.
  static constexpr float kFillFraction = 0.9f;           ///< fraction of the half-view the framed points reach.
  static constexpr std::size_t kMaxFramePoints = 50000;  ///< larger point sets are subsampled (by stride).

  /// Frames a point set: resets yaw/pitch to the defaults, then fits target and distance (see the class
  /// comment). Also sets the scene bounds to the points' bounding box. An empty set frames the unit box.
  void frame(std::span<const QVector3D> points);
  /// Frames the eight corners of the box [lo, hi].
  void frame(const QVector3D& lo, const QVector3D& hi);

  /// Updates the box that the near/far planes must enclose (e.g. after a deformation) without moving the camera.
  /// A degenerate (empty or point) box is widened to a unit box around its centre.
  void setSceneBounds(const QVector3D& lo, const QVector3D& hi);

  /// Sets the viewport size in pixels (width, height ≥ 1 after clamping); refits while the fit is pending.
  void setViewportSize(int width, int height);

  /// Rotates by pixel deltas: 0.4 degree per pixel, dx changes yaw, dy changes pitch.
  void orbit(float dxPixels, float dyPixels);

  /// Moves the target in the view plane so that the point under the target follows the cursor.
  void pan(float dxPixels, float dyPixels);

  /// Dolly by wheel steps (one notch = 1): steps > 0 moves closer (×0.85 per step); clamped to a sane range.
  void zoom(float steps);

  /// Puts the eye at `eye` looking at `target` (a remote user's view to follow): target and distance as given
  /// (clamped like zoom()), yaw and pitch from the direction (pitch clamped to ±89, no roll: the turntable's up).
  /// A degenerate direction (eye == target) keeps the angles. Ends the pending fit, as a user's move does.
  void lookAt(const QVector3D& eye, const QVector3D& target);

  /// World-to-camera matrix.
  [[nodiscard]] QMatrix4x4 view() const;
  /// Camera-to-clip matrix; near/far planes enclose the scene bounds wherever the eye is.
  [[nodiscard]] QMatrix4x4 projection() const;
  /// Eye position in world coordinates.
  [[nodiscard]] QVector3D eye() const;
  /// The camera's up direction in world coordinates (unit length; world +y tilted by the pitch).
  [[nodiscard]] QVector3D up() const;

  [[nodiscard]] QVector3D target() const { return m_target; }
  [[nodiscard]] float distance() const { return m_distance; }
  [[nodiscard]] float yaw() const { return m_yaw; }
  [[nodiscard]] float pitch() const { return m_pitch; }
  [[nodiscard]] float aspect() const { return static_cast<float>(m_width) / static_cast<float>(m_height); }

 private:
  void fit();
  [[nodiscard]] QMatrix4x4 rotation() const;

  std::vector<QVector3D> m_framePoints;
  QVector3D m_lo{-1, -1, -1};
  QVector3D m_hi{1, 1, 1};
  QVector3D m_target{0, 0, 0};
  float m_sceneRadius = 1.0f;
  float m_distance = 5.0f;
  float m_yaw = kDefaultYaw;
  float m_pitch = kDefaultPitch;
  int m_width = 1;
  int m_height = 1;
  bool m_fitPending = true;
};

}  // namespace sc::app
