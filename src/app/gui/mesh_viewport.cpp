#include "app/gui/mesh_viewport.h"

#include "app/gui/mesh_shaders.h"
#include "app/gui/vertex_normals.h"

#include <QMouseEvent>
#include <QOpenGLContext>
#include <QOpenGLShaderProgram>
#include <QWheelEvent>
#include <QtDebug>

#include <cassert>

namespace sc::app {

namespace {

constexpr int kFloatsPerVertex = 6;  // position xyz, normal xyz
const QVector3D kBackgroundTop{0.40f, 0.44f, 0.51f};
const QVector3D kBackgroundBottom{0.11f, 0.12f, 0.15f};
const QVector3D kMeshColor{0.76f, 0.70f, 0.62f};  // warm clay

QVector3D toQVector(const Eigen::RowVector3d& v) {
  return {static_cast<float>(v.x()), static_cast<float>(v.y()), static_cast<float>(v.z())};
}

// Compiles and links a program, or warns with the driver log and returns null.
std::unique_ptr<QOpenGLShaderProgram> makeProgram(const char* vertexSource, const char* fragmentSource) {
  auto program = std::make_unique<QOpenGLShaderProgram>();
  if (!program->addShaderFromSourceCode(QOpenGLShader::Vertex, vertexSource) ||
      !program->addShaderFromSourceCode(QOpenGLShader::Fragment, fragmentSource) || !program->link()) {
    qWarning().noquote() << "MeshViewport: shader program failed:" << program->log();
    return nullptr;
  }
  return program;
}

}  // namespace

QSurfaceFormat MeshViewport::preferredSurfaceFormat() {
  QSurfaceFormat format;
  format.setRenderableType(QSurfaceFormat::OpenGL);
  format.setVersion(3, 3);
  format.setProfile(QSurfaceFormat::CoreProfile);
  format.setDepthBufferSize(24);
  format.setSamples(4);
  return format;
}

MeshViewport::MeshViewport(QWidget* parent) : QOpenGLWidget(parent) {
  setFocusPolicy(Qt::StrongFocus);
  m_F.resize(0, 3);
}

MeshViewport::~MeshViewport() { cleanup(); }

QSize MeshViewport::minimumSizeHint() const { return {200, 150}; }

QSize MeshViewport::sizeHint() const { return {960, 720}; }

void MeshViewport::setMesh(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
  assert(V.cols() == 3 && F.cols() == 3 && "V and F must be #V by 3 and #F by 3");
  if (V.rows() == 0 || F.rows() == 0) {
    clearMesh();
    return;
  }
  const Eigen::RowVector3d lo = V.colwise().minCoeff();
  const Eigen::RowVector3d hi = V.colwise().maxCoeff();
  m_origin = 0.5 * (lo + hi);
  m_F = F;
  m_vertexCount = static_cast<int>(V.rows());
  fillVertexData(V);
  m_indices.resize(static_cast<std::size_t>(F.size()));
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    for (Eigen::Index c = 0; c < 3; ++c) {
      m_indices[static_cast<std::size_t>(3 * f + c)] = static_cast<std::uint32_t>(F(f, c));
    }
  }
  m_indicesDirty = true;
  emit meshChanged();
  resetView();
}

void MeshViewport::setPositions(const Eigen::MatrixXd& V) {
  assert(V.rows() == m_vertexCount && V.cols() == 3 && "setPositions needs the #V of the current mesh");
  if (V.rows() != m_vertexCount || V.cols() != 3 || m_vertexCount == 0) {
    return;
  }
  fillVertexData(V);
  m_camera.setSceneBounds(toQVector(V.colwise().minCoeff() - m_origin), toQVector(V.colwise().maxCoeff() - m_origin));
  update();
}

void MeshViewport::clearMesh() {
  m_F.resize(0, 3);
  m_vertexData.clear();
  m_indices.clear();
  m_vertexCount = 0;
  m_vertexDataDirty = true;
  m_indicesDirty = true;
  emit meshChanged();
  update();
}

void MeshViewport::resetView() {
  std::vector<QVector3D> positions(static_cast<std::size_t>(m_vertexCount));
  for (std::size_t i = 0; i < positions.size(); ++i) {
    const float* p = m_vertexData.data() + kFloatsPerVertex * i;
    positions[i] = QVector3D{p[0], p[1], p[2]};
  }
  m_camera.setViewportSize(width(), height());
  m_camera.frame(positions);
  update();
}

void MeshViewport::fillVertexData(const Eigen::MatrixXd& V) {
  const Eigen::MatrixXd N = vertexNormals(V, m_F);
  m_vertexData.resize(static_cast<std::size_t>(kFloatsPerVertex * V.rows()));
  for (Eigen::Index i = 0; i < V.rows(); ++i) {
    float* out = m_vertexData.data() + kFloatsPerVertex * i;
    for (Eigen::Index k = 0; k < 3; ++k) {
      out[k] = static_cast<float>(V(i, k) - m_origin(k));
      out[3 + k] = static_cast<float>(N(i, k));
    }
  }
  m_vertexDataDirty = true;
}

void MeshViewport::cleanup() {
  if (!m_meshProgram && !m_backgroundProgram && !m_meshVao.isCreated()) {
    return;
  }
  makeCurrent();
  m_vertexBuffer.destroy();
  m_indexBuffer.destroy();
  m_meshVao.destroy();
  m_backgroundVao.destroy();
  m_meshProgram.reset();
  m_backgroundProgram.reset();
  doneCurrent();
  if (context() != nullptr) {
    QObject::disconnect(context(), &QOpenGLContext::aboutToBeDestroyed, this, &MeshViewport::cleanup);
  }
}

void MeshViewport::initializeGL() {
  // The context is destroyed whenever the widget moves to another top-level window; release our objects then,
  // and re-create them here when initializeGL() follows (hellogl2).
  connect(context(), &QOpenGLContext::aboutToBeDestroyed, this, &MeshViewport::cleanup);
  initializeOpenGLFunctions();

  m_backgroundProgram = makeProgram(shaders::kBackgroundVertex, shaders::kBackgroundFragment);
  m_meshProgram = makeProgram(shaders::kMeshVertex, shaders::kMeshFragment);
  m_backgroundVao.create();
  m_meshVao.create();
  if (!m_meshProgram) {
    return;
  }

  // === the mesh VAO records the interleaved attribute layout and the index buffer binding.
  QOpenGLVertexArrayObject::Binder vaoBinder(&m_meshVao);
  m_vertexBuffer.create();
  m_vertexBuffer.setUsagePattern(QOpenGLBuffer::DynamicDraw);
  m_vertexBuffer.bind();
  m_indexBuffer.create();
  m_indexBuffer.setUsagePattern(QOpenGLBuffer::StaticDraw);
  m_indexBuffer.bind();
  constexpr int stride = kFloatsPerVertex * static_cast<int>(sizeof(float));
  m_meshProgram->bind();
  m_meshProgram->enableAttributeArray(0);
  m_meshProgram->enableAttributeArray(1);
  m_meshProgram->setAttributeBuffer(0, GL_FLOAT, 0, 3, stride);
  m_meshProgram->setAttributeBuffer(1, GL_FLOAT, 3 * static_cast<int>(sizeof(float)), 3, stride);
  m_meshProgram->release();
  m_vertexBuffer.release();

  // A new context has empty buffers: upload whatever the host side holds.
  m_vertexDataDirty = true;
  m_indicesDirty = true;
}

void MeshViewport::resizeGL(int width, int height) { m_camera.setViewportSize(width, height); }

void MeshViewport::paintGL() {
  glClearColor(kBackgroundBottom.x(), kBackgroundBottom.y(), kBackgroundBottom.z(), 1.0f);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  drawBackground();
  if (m_meshProgram) {
    uploadIfDirty();
    drawMesh();
  }
}

void MeshViewport::uploadIfDirty() {
  if (m_vertexDataDirty) {
    m_vertexBuffer.bind();
    m_vertexBuffer.allocate(m_vertexData.data(), static_cast<int>(m_vertexData.size() * sizeof(float)));
    m_vertexBuffer.release();
    m_vertexDataDirty = false;
  }
  if (m_indicesDirty) {
    QOpenGLVertexArrayObject::Binder vaoBinder(&m_meshVao);
    m_indexBuffer.bind();  // stays bound: the element array binding is VAO state
    m_indexBuffer.allocate(m_indices.data(), static_cast<int>(m_indices.size() * sizeof(std::uint32_t)));
    m_indicesDirty = false;
  }
}

void MeshViewport::drawBackground() {
  if (!m_backgroundProgram) {
    return;
  }
  glDisable(GL_DEPTH_TEST);
  glDepthMask(GL_FALSE);
  m_backgroundProgram->bind();
  m_backgroundProgram->setUniformValue("uTopColor", kBackgroundTop);
  m_backgroundProgram->setUniformValue("uBottomColor", kBackgroundBottom);
  QOpenGLVertexArrayObject::Binder vaoBinder(&m_backgroundVao);
  glDrawArrays(GL_TRIANGLES, 0, 3);
  m_backgroundProgram->release();
  glDepthMask(GL_TRUE);
}

void MeshViewport::drawMesh() {
  if (m_indices.empty()) {
    return;
  }
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  const QMatrix4x4 modelView = m_camera.view();
  m_meshProgram->bind();
  m_meshProgram->setUniformValue("uModelView", modelView);
  m_meshProgram->setUniformValue("uNormalMatrix", modelView.normalMatrix());
  m_meshProgram->setUniformValue("uProjection", m_camera.projection());
  m_meshProgram->setUniformValue("uBaseColor", kMeshColor);
  QOpenGLVertexArrayObject::Binder vaoBinder(&m_meshVao);
  glDrawElements(GL_TRIANGLES, static_cast<GLsizei>(m_indices.size()), GL_UNSIGNED_INT, nullptr);
  m_meshProgram->release();
}

void MeshViewport::mousePressEvent(QMouseEvent* event) { m_lastMousePos = event->position().toPoint(); }

void MeshViewport::mouseMoveEvent(QMouseEvent* event) {
  const QPoint pos = event->position().toPoint();
  const QPoint delta = pos - m_lastMousePos;
  m_lastMousePos = pos;
  if (event->buttons() & Qt::LeftButton) {
    m_camera.orbit(static_cast<float>(delta.x()), static_cast<float>(delta.y()));
  } else if (event->buttons() & (Qt::RightButton | Qt::MiddleButton)) {
    m_camera.pan(static_cast<float>(delta.x()), static_cast<float>(delta.y()));
  } else {
    return;
  }
  update();
}

void MeshViewport::mouseDoubleClickEvent(QMouseEvent* /*event*/) { resetView(); }

void MeshViewport::wheelEvent(QWheelEvent* event) {
  m_camera.zoom(static_cast<float>(event->angleDelta().y()) / 120.0f);
  update();
  event->accept();
}

}  // namespace sc::app
