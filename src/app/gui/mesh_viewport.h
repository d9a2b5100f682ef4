#pragma once
// MeshViewport: an OpenGL 3.3 core view of one triangle mesh, with orbit/pan/zoom, a selection brush and a handle
// drag. View only: the camera math lives in OrbitCamera, the normals in vertexNormals(), picking in
// vertex_picking.h and the drag pose in DragGesture; this class owns the GL objects and the host-side buffers and
// turns mouse gestures into intent signals (handlePainted, dragMoved, …) that a controller maps to session calls.

#include "app/gui/orbit_camera.h"
#include "app/gui/vertex_picking.h"

#include <Eigen/Core>

#include <QOpenGLBuffer>
#include <QOpenGLFunctions>
#include <QOpenGLVertexArrayObject>
#include <QOpenGLWidget>
#include <QPoint>
#include <QString>
#include <QSurfaceFormat>
#include <QTimer>

#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <vector>

class QOpenGLFramebufferObject;
class QOpenGLFunctions_3_3_Core;
class QOpenGLShaderProgram;

namespace sc::app {

class DragGesture;

/// What a left drag does in the viewport. Right/middle drag always pans and the wheel always zooms.
enum class ViewportTool {
  Orbit,        ///< left drag orbits the camera (the default).
  HandleBrush,  ///< left drag paints handle vertices, Shift+left drag erases them.
  AnchorBrush,  ///< left drag paints anchor vertices, Shift+left drag erases them.
  Drag,         ///< left drag on the mesh moves the handle (Ctrl: rotates it); off the mesh it orbits.
};

/// Renders a triangle mesh with area-weighted vertex normals, two-light Blinn–Phong shading over a vertical
/// gradient background, framed on its vertices; optionally with its edges drawn over it (wireframe) and with the
/// handle (orange-red) and anchor (blue) vertices tinted.
///
/// Mouse: see ViewportTool; a double click re-frames. Brush picking is a real visibility test: at the start of
/// each stroke the mesh is rendered into an offscreen depth buffer that is read back, and only vertices within
/// brushRadius() pixels of the cursor whose depth matches the rendered surface are painted (projectToScreen()).
///
/// GL lifetime follows Qt's hellogl2: nothing GL happens in the constructor; GL objects are made in
/// initializeGL() and released in cleanup(), which runs on QOpenGLContext::aboutToBeDestroyed and in the
/// destructor. Setters only update host-side data, mark it dirty and call update(); paintGL() uploads lazily.
///
/// Signals carry std::vector / Eigen values and are meant for direct (same-thread) connections.
class MeshViewport : public QOpenGLWidget, protected QOpenGLFunctions {
  Q_OBJECT
  Q_DISABLE_COPY_MOVE(MeshViewport)

 public:
  static constexpr double kDefaultBrushRadius = 30.0;  ///< pixels.
  static constexpr int kHintMilliseconds = 2000;       ///< how long a drag hint stays on screen.

  /// The format this widget needs (OpenGL 3.3 core, 24-bit depth, 4× multisampling). Pass it to
  /// QSurfaceFormat::setDefaultFormat() before constructing the QApplication.
  static QSurfaceFormat preferredSurfaceFormat();

  explicit MeshViewport(QWidget* parent = nullptr);
  ~MeshViewport() override;

  /// Replaces the mesh, computes vertex normals and frames the camera on it (resetView()). Clears the selection
  /// (without emitting handlePainted/anchorsPainted) and ends any gesture.
  /// @param[in] V  #V by 3 positions (finite).
  /// @param[in] F  #F by 3 indices into V.
  /// Emits meshChanged(). An empty V or F shows the background only.
  void setMesh(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F);

  /// Moves the vertices of the current mesh (e.g. one deformation frame) and recomputes the normals.
  /// @param[in] V  #V by 3 positions, same #V as the mesh given to setMesh().
  /// Does not re-frame the camera and does not emit meshChanged(). A V with another row count is a programming
  /// error: asserted in debug builds, ignored in release builds.
  void setPositions(const Eigen::MatrixXd& V);

  /// The per-frame fast path of setPositions(): the same contract, from flat floats, with no Eigen conversion.
  /// @param[in] xyz  3·#V floats, x y z per vertex, in the coordinates given to setMesh().
  /// Recomputes the normals in float (O(#V + #F)); the upload happens in the next paintGL().
  void setPositionsInterleaved(std::span<const float> xyz);

  /// Removes the mesh (background only). Emits meshChanged().
  void clearMesh();

  /// Sets the vertices shown as handle (orange-red) and anchors (blue). Indices outside [0, #V) are dropped;
  /// the rest are sorted and de-duplicated. A vertex in both sets shows as a handle. Emits nothing.
  void setSelection(std::vector<int> handles, std::vector<int> anchors);
  [[nodiscard]] const std::vector<int>& handles() const { return m_handles; }
  [[nodiscard]] const std::vector<int>& anchors() const { return m_anchors; }

  /// Chooses what a left drag does; ends a gesture in progress (a drag in progress emits dragFinished()).
  void setTool(ViewportTool tool);
  [[nodiscard]] ViewportTool tool() const { return m_tool; }

  /// Brush radius in widget (logical) pixels; clamped to ≥ 1.
  void setBrushRadius(double pixels);
  [[nodiscard]] double brushRadius() const { return m_brushRadius; }

  /// Whether the Drag tool may move the handle (e.g. while this peer holds the edit lock). When not allowed, a
  /// left press with the Drag tool emits nothing and shows `hint` over the view for kHintMilliseconds.
  /// Revoking it during a drag ends that drag with dragFinished().
  void setDragAllowed(bool allowed, const QString& hint = {});
  [[nodiscard]] bool dragAllowed() const { return m_dragAllowed; }
  /// The hint currently shown over the view, or an empty string.
  [[nodiscard]] QString visibleHint() const { return m_visibleHint; }

  /// Draws the triangle edges over the shaded mesh (a GL_LINE pass over a polygon-offset fill).
  void setWireframe(bool on);
  [[nodiscard]] bool wireframe() const { return m_wireframe; }

  [[nodiscard]] int vertexCount() const { return m_vertexCount; }
  [[nodiscard]] int triangleCount() const { return static_cast<int>(m_indices.size() / 3); }
  [[nodiscard]] const OrbitCamera& camera() const { return m_camera; }

  [[nodiscard]] QSize minimumSizeHint() const override;
  [[nodiscard]] QSize sizeHint() const override;

 public slots:
  /// Re-frames the camera on the mesh's current vertices, with the default view angles.
  void resetView();
  /// Same as resetView() (the name the View menu uses).
  void fitToView() { resetView(); }
  /// Releases the GL objects; safe to call more than once and without a context ever having existed.
  void cleanup();

 signals:
  /// The mesh was replaced or removed.
  void meshChanged();
  /// A handle-brush stroke ended; `handles` is the full handle set now shown (sorted, unique).
  void handlePainted(std::vector<int> handles);
  /// An anchor-brush stroke ended; `anchors` is the full anchor set now shown (sorted, unique).
  void anchorsPainted(std::vector<int> anchors);
  /// A handle drag began (the Drag tool, allowed, a non-empty handle, pressed on the mesh).
  void dragStarted();
  /// The pose of the handle since dragStarted(): x ↦ rotation·(x − c) + c + translation, c the handle centroid
  /// at the start of the drag, in the coordinates given to setMesh() (see DragGesture).
  void dragMoved(Eigen::Vector3d translation, Eigen::Matrix3d rotation);
  /// The drag ended (mouse released, tool changed, drag revoked or mesh replaced).
  void dragFinished();

 protected:
  void initializeGL() override;
  void paintGL() override;
  void resizeGL(int width, int height) override;
  void mousePressEvent(QMouseEvent* event) override;
  void mouseMoveEvent(QMouseEvent* event) override;
  void mouseReleaseEvent(QMouseEvent* event) override;
  void mouseDoubleClickEvent(QMouseEvent* event) override;
  void wheelEvent(QWheelEvent* event) override;

 private:
  enum class Gesture { None, Camera, Paint, Drag, Blocked };

  // GL side (mesh_viewport.cpp).
  void positionsChanged();
  void rebuildTints();
  void uploadIfDirty();
  void drawBackground();
  void drawMesh(bool wireframe);
  void drawOverlay();
  [[nodiscard]] DepthImage renderDepth();

  // Input side (mesh_viewport_input.cpp).
  void beginStroke();
  void paintDab(QPointF pos, bool erase);
  bool beginDrag(QPointF pos);
  void endGesture();
  void showHint(const QString& text);
  [[nodiscard]] std::vector<int>& brushSelection();

  OrbitCamera m_camera;

  // Host side. Positions are stored relative to m_origin (the bounding-box centre at setMesh()) so that float
  // precision is spent on the shape, not on its placement.
  Eigen::RowVector3d m_origin = Eigen::RowVector3d::Zero();
  std::vector<float> m_positions;        // 3·#V, relative to m_origin
  std::vector<float> m_normals;          // 3·#V
  std::vector<std::uint8_t> m_tints;     // 4·#V, RGBA (A = tint strength)
  std::vector<std::uint32_t> m_indices;  // 3·#F
  int m_vertexCount = 0;
  bool m_vertexDataDirty = false;
  bool m_tintsDirty = false;
  bool m_indicesDirty = false;
  std::vector<int> m_handles;
  std::vector<int> m_anchors;
  bool m_wireframe = false;

  // Interaction.
  ViewportTool m_tool = ViewportTool::Orbit;
  double m_brushRadius = kDefaultBrushRadius;
  bool m_dragAllowed = true;
  QString m_dragHint;
  QString m_visibleHint;
  QTimer m_hintTimer;
  Gesture m_gesture = Gesture::None;
  QPoint m_lastMousePos;
  std::optional<QPointF> m_cursor;          // for the brush outline
  std::vector<ScreenPoint> m_strokePoints;  // projected at the start of a stroke
  std::unique_ptr<DragGesture> m_drag;

  // GL side (valid between initializeGL() and cleanup()).
  std::unique_ptr<QOpenGLShaderProgram> m_meshProgram;
  std::unique_ptr<QOpenGLShaderProgram> m_backgroundProgram;
  std::unique_ptr<QOpenGLFramebufferObject> m_pickFbo;
  QOpenGLFunctions_3_3_Core* m_gl33 = nullptr;  // for glPolygonMode; owned by the context
  QOpenGLVertexArrayObject m_meshVao;
  QOpenGLVertexArrayObject m_backgroundVao;
  QOpenGLBuffer m_positionBuffer{QOpenGLBuffer::VertexBuffer};
  QOpenGLBuffer m_normalBuffer{QOpenGLBuffer::VertexBuffer};
  QOpenGLBuffer m_tintBuffer{QOpenGLBuffer::VertexBuffer};
  QOpenGLBuffer m_indexBuffer{QOpenGLBuffer::IndexBuffer};
};

}  // namespace sc::app
