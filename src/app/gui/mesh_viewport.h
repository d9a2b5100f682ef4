#pragma once
// MeshViewport: an OpenGL 3.3 core view of one triangle mesh, with orbit/pan/zoom. View only: the camera math lives
// in OrbitCamera and the normals in vertexNormals(); this class owns the GL objects and the host-side buffers.

#include "app/gui/orbit_camera.h"

#include <Eigen/Core>

#include <QOpenGLBuffer>
#include <QOpenGLFunctions>
#include <QOpenGLVertexArrayObject>
#include <QOpenGLWidget>
#include <QPoint>
#include <QSurfaceFormat>

#include <cstdint>
#include <memory>
#include <vector>

class QOpenGLShaderProgram;

namespace sc::app {

/// Renders a triangle mesh with area-weighted vertex normals, two-light Blinn–Phong shading over a vertical
/// gradient background, framed on its vertices.
///
/// Mouse: left drag orbits (turntable), right or middle drag pans, the wheel zooms, a double click re-frames.
///
/// GL lifetime follows Qt's hellogl2: nothing GL happens in the constructor; GL objects are made in
/// initializeGL() and released in cleanup(), which runs on QOpenGLContext::aboutToBeDestroyed and in the
/// destructor. Setters only update host-side data, mark it dirty and call update(); paintGL() uploads lazily.
class MeshViewport : public QOpenGLWidget, protected QOpenGLFunctions {
  Q_OBJECT
  Q_DISABLE_COPY_MOVE(MeshViewport)

 public:
  /// The format this widget needs (OpenGL 3.3 core, 24-bit depth, 4× multisampling). Pass it to
  /// QSurfaceFormat::setDefaultFormat() before constructing the QApplication.
  static QSurfaceFormat preferredSurfaceFormat();

  explicit MeshViewport(QWidget* parent = nullptr);
  ~MeshViewport() override;

  /// Replaces the mesh, computes vertex normals and frames the camera on it (resetView()).
  /// @param[in] V  #V by 3 positions (finite).
  /// @param[in] F  #F by 3 indices into V.
  /// Emits meshChanged(). An empty V or F shows the background only.
  void setMesh(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F);

  /// Moves the vertices of the current mesh (e.g. one deformation frame) and recomputes the normals.
  /// @param[in] V  #V by 3 positions, same #V as the mesh given to setMesh().
  /// Does not re-frame the camera and does not emit meshChanged(). A V with another row count is a programming
  /// error: asserted in debug builds, ignored in release builds.
  void setPositions(const Eigen::MatrixXd& V);

  /// Removes the mesh (background only). Emits meshChanged().
  void clearMesh();

  [[nodiscard]] int vertexCount() const { return m_vertexCount; }
  [[nodiscard]] int triangleCount() const { return static_cast<int>(m_indices.size() / 3); }
  [[nodiscard]] const OrbitCamera& camera() const { return m_camera; }

  [[nodiscard]] QSize minimumSizeHint() const override;
  [[nodiscard]] QSize sizeHint() const override;

 public slots:
  /// Re-frames the camera on the mesh's current vertices, with the default view angles.
  void resetView();
  /// Releases the GL objects; safe to call more than once and without a context ever having existed.
  void cleanup();

 signals:
  /// The mesh was replaced or removed.
  void meshChanged();

 protected:
  void initializeGL() override;
  void paintGL() override;
  void resizeGL(int width, int height) override;
  void mousePressEvent(QMouseEvent* event) override;
  void mouseMoveEvent(QMouseEvent* event) override;
  void mouseDoubleClickEvent(QMouseEvent* event) override;
  void wheelEvent(QWheelEvent* event) override;

 private:
  void fillVertexData(const Eigen::MatrixXd& V);
  void uploadIfDirty();
  void drawBackground();
  void drawMesh();

  OrbitCamera m_camera;

  // Host side. Positions are stored relative to m_origin (the bounding-box centre at setMesh()) so that float
  // precision is spent on the shape, not on its placement.
  Eigen::MatrixXi m_F;
  Eigen::RowVector3d m_origin = Eigen::RowVector3d::Zero();
  std::vector<float> m_vertexData;  // interleaved: x y z nx ny nz per vertex
  std::vector<std::uint32_t> m_indices;
  int m_vertexCount = 0;
  bool m_vertexDataDirty = false;
  bool m_indicesDirty = false;

  // GL side (valid between initializeGL() and cleanup()).
  std::unique_ptr<QOpenGLShaderProgram> m_meshProgram;
  std::unique_ptr<QOpenGLShaderProgram> m_backgroundProgram;
  QOpenGLVertexArrayObject m_meshVao;
  QOpenGLVertexArrayObject m_backgroundVao;
  QOpenGLBuffer m_vertexBuffer{QOpenGLBuffer::VertexBuffer};
  QOpenGLBuffer m_indexBuffer{QOpenGLBuffer::IndexBuffer};

  QPoint m_lastMousePos;
};

}  // namespace sc::app
