#pragma once
// An orbit camera around a target point (turntable or trackball, y or z up, standard views): the view math behind
// MeshViewport, free of any GL or widget.

#include <QMatrix4x4>
#include <QQuaternion>
#include <QVector3D>

#include <optional>
#include <span>
#include <vector>

namespace sc::app {

/// Which world axis points up on screen in the turntable and the standard views.
enum class UpAxis { Y, Z };

/// How a left drag turns the view: a turntable (yaw about the up axis, pitch clamped to ±89°, never any roll) or a
/// trackball (free rotation about the screen axis perpendicular to the drag; it may roll and go over the poles).
enum class RotationMode { Turntable, Trackball };

/// The views of View → Standard Views. Home: the default three-quarter view from the front, left and above
/// (kDefaultYaw, kDefaultPitch). Front looks at the mesh from its front: the eye on +z for y up, on −y for z up
/// (Blender's convention); Right from +x; Top from +up with the front at the bottom of the screen.
enum class StandardView { Home, Front, Back, Left, Right, Top, Bottom };

/// Orbit camera. The eye sits on a sphere of radius distance() around target(). Its orientation is given in the
/// "up space", the world rotated so that the chosen up axis is +y (identity for UpAxis::Y; for UpAxis::Z,
/// (x, y, z) ↦ (x, z, −y)): angles yaw (about the up axis, degrees) and pitch (elevation, degrees, within ±90; a
/// turntable drag keeps it within ±89) in turntable mode, a free rotation in trackball mode (yaw() and pitch() then
/// report the eye's direction). Projection is perspective with a fixed vertical field of view.
///
/// Framing contract: frame() centres and fits a point set (a mesh's vertices) so that, in perspective, its
/// extreme points sit symmetrically at kFillFraction of the half-view on the tighter axis. Until the user orbits,
/// pans or zooms, the fit is redone whenever the viewport size changes, so a mesh framed before its widget is
/// shown is still framed for the final size.
class OrbitCamera {
 public:
  static constexpr float kFieldOfViewY = 30.0f;          ///< vertical field of view, degrees.
  static constexpr float kDefaultYaw = 35.0f;            ///< initial yaw after frame(), degrees.
  static constexpr float kDefaultPitch = 18.0f;          ///< initial elevation after frame(), degrees.
  static constexpr float kFillFraction = 0.9f;           ///< fraction of the half-view the framed points reach.
  static constexpr std::size_t kMaxFramePoints = 50000;  ///< larger point sets are subsampled (by stride).

  /// Frames a point set: turns to `view` (nullopt: keeps the current orientation, "fit"), then fits target and
  /// distance (see the class comment). Also sets the scene bounds to the points' bounding box. An empty set frames
  /// the unit box. Cost: O(#points) up to kMaxFramePoints, then by stride.
  void frame(std::span<const QVector3D> points, std::optional<StandardView> view = StandardView::Home);
  /// Frames the eight corners of the box [lo, hi].
  void frame(const QVector3D& lo, const QVector3D& hi, std::optional<StandardView> view = StandardView::Home);

  /// Chooses the up axis; the view turns to Home and refits on the points last framed.
  void setUpAxis(UpAxis axis);
  [[nodiscard]] UpAxis upAxis() const { return m_upAxis; }
  /// Chooses turntable or trackball rotation; the view does not move (going back to the turntable drops any roll).
  void setRotationMode(RotationMode mode);
  [[nodiscard]] RotationMode rotationMode() const { return m_mode; }

  /// Moves the orbit pivot (the target) to `pivot` keeping the orientation: the eye moves in its view plane (a pan)
  /// until the pivot is at the centre of the screen; the distance becomes the pivot's depth (clamped like zoom()).
  /// Ends the pending fit.
  void setPivot(const QVector3D& pivot);

  /// Updates the box that the near/far planes must enclose (e.g. after a deformation) without moving the camera.
  /// A degenerate (empty or point) box is widened to a unit box around its centre.
  void setSceneBounds(const QVector3D& lo, const QVector3D& hi);

  /// Sets the viewport size in pixels (width, height ≥ 1 after clamping); refits while the fit is pending.
  void setViewportSize(int width, int height);

  /// Rotates by pixel deltas, 0.4 degree per pixel. Turntable: dx changes yaw, dy pitch. Trackball: the scene turns
  /// about the screen axis perpendicular to the drag (for a pure dx or dy the same first step as the turntable's).
  void orbit(float dxPixels, float dyPixels);

  /// Moves the target in the view plane so that the point under the target follows the cursor.
  void pan(float dxPixels, float dyPixels);

  /// Dolly by wheel steps (one notch = 1): steps > 0 moves closer (×0.85 per step); clamped to a sane range.
  void zoom(float steps);

  /// Puts the eye at `eye` looking at `target` (a remote user's view to follow): target and distance as given
  /// (clamped like zoom()), yaw and pitch from the direction in the up space (pitch clamped to ±89, no roll).
  /// A degenerate direction (eye == target) keeps the angles. Ends the pending fit, as a user's move does.
  void lookAt(const QVector3D& eye, const QVector3D& target);

  /// World-to-camera matrix.
  [[nodiscard]] QMatrix4x4 view() const;
  /// Camera-to-clip matrix; near/far planes enclose the scene bounds wherever the eye is.
  [[nodiscard]] QMatrix4x4 projection() const;
  /// Eye position in world coordinates.
  [[nodiscard]] QVector3D eye() const;
  /// The camera's up direction in world coordinates (unit length; the up axis tilted by the pitch, or the
  /// trackball's).
  [[nodiscard]] QVector3D up() const;

  [[nodiscard]] QVector3D target() const { return m_target; }
  [[nodiscard]] float distance() const { return m_distance; }
  [[nodiscard]] float yaw() const { return m_yaw; }
  [[nodiscard]] float pitch() const { return m_pitch; }
  [[nodiscard]] float aspect() const { return static_cast<float>(m_width) / static_cast<float>(m_height); }

 private:
  void fit();
  /// Turns to `view` (angles and, in trackball mode, the trackball's rotation).
  void orient(StandardView view);
  /// Sets yaw and pitch from an eye direction in world coordinates (no-op for a zero vector).
  void aimFrom(const QVector3D& back);
  /// World-to-camera rotation: the turntable's or the trackball's, after the up space's rotation.
  [[nodiscard]] QMatrix4x4 rotation() const;
  [[nodiscard]] QQuaternion turntable() const;
  [[nodiscard]] QQuaternion upSpace() const;

  std::vector<QVector3D> m_framePoints;
  QVector3D m_lo{-1, -1, -1};
  QVector3D m_hi{1, 1, 1};
  QVector3D m_target{0, 0, 0};
  float m_sceneRadius = 1.0f;
  float m_distance = 5.0f;
  float m_yaw = kDefaultYaw;
  float m_pitch = kDefaultPitch;
  UpAxis m_upAxis = UpAxis::Y;
  RotationMode m_mode = RotationMode::Turntable;
  QQuaternion m_trackball;  // up-space-to-camera rotation in trackball mode
  int m_width = 1;
  int m_height = 1;
  bool m_fitPending = true;
};

}  // namespace sc::app
