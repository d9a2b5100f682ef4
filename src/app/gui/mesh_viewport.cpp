// MeshViewport, the data and GL side: host buffers, upload, the shaded/wireframe/overlay passes and the depth
// read-back used for picking. The mouse side is in mesh_viewport_input.cpp.

#include "app/gui/mesh_viewport.h"

#include "app/gui/drag_gesture.h"
#include "app/gui/mesh_shaders.h"
#include "app/gui/vertex_normals.h"

#include <QOffscreenSurface>
#include <QOpenGLContext>
#include <QOpenGLFramebufferObject>
#include <QOpenGLFunctions_3_3_Core>
#include <QOpenGLShaderProgram>
#include <QOpenGLVersionFunctionsFactory>
#include <QPainter>
#include <QtDebug>

#include <algorithm>
#include <cassert>
#include <limits>

namespace sc::app {

namespace {

const QVector3D kBackgroundTop{0.40f, 0.44f, 0.51f};
const QVector3D kBackgroundBottom{0.11f, 0.12f, 0.15f};
const QVector3D kMeshColor{0.76f, 0.70f, 0.62f};  // warm clay
const QVector4D kWireColor{0.16f, 0.14f, 0.13f, 1.0f};
constexpr std::uint8_t kHandleTint[4] = {255, 72, 20, 230};   // orange-red
constexpr std::uint8_t kAnchorTint[4] = {40, 110, 255, 210};  // blue

}  // namespace

QSurfaceFormat MeshViewport::preferredSurfaceFormat() {
  QSurfaceFormat format;
  format.setRenderableType(QSurfaceFormat::OpenGL);
  format.setVersion(3, 3);
  format.setProfile(QSurfaceFormat::CoreProfile);
  format.setDepthBufferSize(24);
  return format;
}

QString MeshViewport::rendererName() {
  QOpenGLContext context;
  context.setFormat(QSurfaceFormat::defaultFormat());
  if (!context.create()) {
    return {};
  }
  QOffscreenSurface surface;
  surface.setFormat(context.format());
  surface.create();
  if (!context.makeCurrent(&surface)) {
    return {};
  }
  const auto* name = reinterpret_cast<const char*>(context.functions()->glGetString(GL_RENDERER));
  QString result = name != nullptr ? QString::fromLatin1(name) : QString();
  context.doneCurrent();
  return result;
}

int MeshViewport::defaultSampleCount() {
  static const int samples = [] {
    bool ok = false;
    const int fromEnvironment = qEnvironmentVariableIntValue("SHAPECAST_MSAA", &ok);
    if (ok) {
      return std::max(0, fromEnvironment);
    }
    const QString renderer = rendererName().toLower();
    const bool software = renderer.contains(QLatin1String("llvmpipe")) ||
                          renderer.contains(QLatin1String("softpipe")) || renderer.contains(QLatin1String("software"));
    return software ? 0 : 4;
  }();
  return samples;
}

void MeshViewport::setSampleCount(int samples) {
  QSurfaceFormat f = format();
  f.setSamples(std::max(0, samples));
  setFormat(f);
}

MeshViewport::MeshViewport(QWidget* parent) : QOpenGLWidget(parent) {
  setSampleCount(defaultSampleCount());
  setFocusPolicy(Qt::StrongFocus);
  setMouseTracking(true);  // the brush outline follows the cursor
  m_hintTimer.setSingleShot(true);
  m_hintTimer.setInterval(kHintMilliseconds);
  connect(&m_hintTimer, &QTimer::timeout, this, [this] {
    m_visibleHint.clear();
    update();
  });
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
  endGesture();
  dropBasis();
  const Eigen::RowVector3d lo = V.colwise().minCoeff();
  const Eigen::RowVector3d hi = V.colwise().maxCoeff();
  m_origin = 0.5 * (lo + hi);
  m_vertexCount = static_cast<int>(V.rows());
  m_indices.resize(static_cast<std::size_t>(F.size()));
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    for (Eigen::Index c = 0; c < 3; ++c) {
      m_indices[static_cast<std::size_t>(3 * f + c)] = static_cast<std::uint32_t>(F(f, c));
    }
  }
  m_indicesDirty = true;
  setPositions(V);
  m_handles.clear();
  m_anchors.clear();
  rebuildTints();
  emit meshChanged();
  resetView();
}

void MeshViewport::setPositions(const Eigen::MatrixXd& V) {
  assert(V.rows() == m_vertexCount && V.cols() == 3 && "setPositions needs the #V of the current mesh");
  if (V.rows() != m_vertexCount || V.cols() != 3 || m_vertexCount == 0) {
    return;
  }
  m_showingCoefficients = false;
  m_hostPositionsStale = false;
  m_positions.resize(static_cast<std::size_t>(3 * V.rows()));
  for (Eigen::Index i = 0; i < V.rows(); ++i) {
    for (Eigen::Index k = 0; k < 3; ++k) {
      m_positions[static_cast<std::size_t>(3 * i + k)] = static_cast<float>(V(i, k) - m_origin(k));
    }
  }
  positionsChanged();
}

void MeshViewport::setPositionsInterleaved(std::span<const float> xyz) {
  const auto n = static_cast<std::size_t>(m_vertexCount);
  assert(xyz.size() == 3 * n && "setPositionsInterleaved needs 3 floats per vertex of the current mesh");
  if (xyz.size() != 3 * n || n == 0) {
    return;
  }
  m_showingCoefficients = false;
  m_hostPositionsStale = false;
  const float origin[3] = {static_cast<float>(m_origin(0)), static_cast<float>(m_origin(1)),
                           static_cast<float>(m_origin(2))};
  m_positions.resize(3 * n);
  for (std::size_t i = 0; i < 3 * n; ++i) {
    m_positions[i] = xyz[i] - origin[i % 3];
  }
  positionsChanged();
}

// m_positions changed: recompute the normals and the scene bounds, mark the upload and repaint.
void MeshViewport::positionsChanged() {
  m_normals.resize(m_positions.size());
  vertexNormals(m_positions, m_indices, m_normals);
  updateBounds();
  m_vertexDataDirty = true;
  update();
}

// The camera's scene bounds from m_positions (exact), or on the GPU path from the rest bounds widened by
// max_i ‖K_i‖·‖Z_c‖ ≥ |(K·Z)_ic| per coordinate (Cauchy–Schwarz), which needs no reconstruction.
void MeshViewport::updateBounds() {
  if (m_showingCoefficients && m_hostPositionsStale) {
    const Eigen::Vector3f reach = m_basisMaxRowNorm * m_coefficients.colwise().norm().transpose();
    const Eigen::Vector3f lo = m_restLo - reach;
    const Eigen::Vector3f hi = m_restHi + reach;
    m_camera.setSceneBounds(QVector3D(lo.x(), lo.y(), lo.z()), QVector3D(hi.x(), hi.y(), hi.z()));
    return;
  }
  QVector3D lo(std::numeric_limits<float>::max(), std::numeric_limits<float>::max(), std::numeric_limits<float>::max());
  QVector3D hi = -lo;
  for (std::size_t i = 0; i < m_positions.size(); i += 3) {
    const QVector3D p(m_positions[i], m_positions[i + 1], m_positions[i + 2]);
    lo = QVector3D(std::min(lo.x(), p.x()), std::min(lo.y(), p.y()), std::min(lo.z(), p.z()));
    hi = QVector3D(std::max(hi.x(), p.x()), std::max(hi.y(), p.y()), std::max(hi.z(), p.z()));
  }
  m_camera.setSceneBounds(lo, hi);
}

void MeshViewport::clearMesh() {
  endGesture();
  dropBasis();
  m_positions.clear();
  m_normals.clear();
  m_indices.clear();
  m_handles.clear();
  m_anchors.clear();
  m_vertexCount = 0;
  rebuildTints();
  m_vertexDataDirty = true;
  m_indicesDirty = true;
  emit meshChanged();
  update();
}

void MeshViewport::setSelection(std::vector<int> handles, std::vector<int> anchors) {
  for (std::vector<int>* set : {&handles, &anchors}) {
    std::erase_if(*set, [this](int i) { return i < 0 || i >= m_vertexCount; });
    std::sort(set->begin(), set->end());
    set->erase(std::unique(set->begin(), set->end()), set->end());
  }
  m_handles = std::move(handles);
  m_anchors = std::move(anchors);
  rebuildTints();
  update();
}

void MeshViewport::rebuildTints() {
  m_tints.assign(4 * static_cast<std::size_t>(m_vertexCount), 0);
  for (const auto& [set, tint] : {std::pair{&m_anchors, kAnchorTint}, std::pair{&m_handles, kHandleTint}}) {
    for (const int v : *set) {
      std::copy(tint, tint + 4, m_tints.begin() + 4 * static_cast<std::ptrdiff_t>(v));
    }
  }
  m_tintsDirty = true;
}

void MeshViewport::setWireframe(bool on) {
  m_wireframe = on;
  update();
}

void MeshViewport::resetView() {
  ensureHostPositions();
  std::vector<QVector3D> points(static_cast<std::size_t>(m_vertexCount));
  for (std::size_t i = 0; i < points.size(); ++i) {
    points[i] = QVector3D{m_positions[3 * i], m_positions[3 * i + 1], m_positions[3 * i + 2]};
  }
  m_camera.setViewportSize(width(), height());
  m_camera.frame(points);
  update();
}

void MeshViewport::cleanup() {
  if (!m_meshProgram && !m_backgroundProgram && !m_meshVao.isCreated()) {
    return;
  }
  makeCurrent();
  m_glReady = false;
  destroyGpuObjects();
  m_pickFbo.reset();
  for (QOpenGLBuffer* buffer : {&m_positionBuffer, &m_normalBuffer, &m_tintBuffer, &m_indexBuffer}) {
    buffer->destroy();
  }
  m_meshVao.destroy();
  m_backgroundVao.destroy();
  m_meshProgram.reset();
  m_backgroundProgram.reset();
  m_gl33 = nullptr;
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
  m_gl33 = QOpenGLVersionFunctionsFactory::get<QOpenGLFunctions_3_3_Core>(context());

  m_backgroundProgram = shaders::makeProgram(shaders::kBackgroundVertex, shaders::kBackgroundFragment);
  m_meshProgram = shaders::makeProgram(shaders::kMeshVertex, shaders::kMeshFragment);
  m_backgroundVao.create();
  m_meshVao.create();
  if (!m_meshProgram) {
    return;
  }

  // === the mesh VAO records one buffer per attribute (positions change per frame, tints per selection) and
  // the index buffer binding.
  QOpenGLVertexArrayObject::Binder vaoBinder(&m_meshVao);
  m_meshProgram->bind();
  struct Attribute {
    QOpenGLBuffer* buffer;
    GLenum type;
    int size;
  };
  const Attribute attributes[] = {
      {&m_positionBuffer, GL_FLOAT, 3}, {&m_normalBuffer, GL_FLOAT, 3}, {&m_tintBuffer, GL_UNSIGNED_BYTE, 4}};
  for (int location = 0; location < 3; ++location) {
    const Attribute& a = attributes[location];
    a.buffer->create();
    a.buffer->setUsagePattern(location == 2 ? QOpenGLBuffer::StaticDraw : QOpenGLBuffer::DynamicDraw);
    a.buffer->bind();
    m_meshProgram->enableAttributeArray(location);
    if (a.type == GL_UNSIGNED_BYTE) {
      glVertexAttribPointer(static_cast<GLuint>(location), a.size, a.type, GL_TRUE, 0, nullptr);
    } else {
      m_meshProgram->setAttributeBuffer(location, a.type, 0, a.size, 0);
    }
    a.buffer->release();
  }
  m_indexBuffer.create();
  m_indexBuffer.setUsagePattern(QOpenGLBuffer::StaticDraw);
  m_indexBuffer.bind();
  m_meshProgram->release();
  vaoBinder.release();
  createGpuObjects();

  // A new context has empty buffers: upload whatever the host side holds.
  m_vertexDataDirty = true;
  m_tintsDirty = true;
  m_indicesDirty = true;
  m_glReady = true;
  if (m_path == ReconstructionPath::Gpu && hasReconstructionBasis() && !gpuReconstructionAvailable()) {
    setReconstructionPath(ReconstructionPath::Cpu);
  }
}

void MeshViewport::resizeGL(int width, int height) { m_camera.setViewportSize(width, height); }

void MeshViewport::paintGL() {
  ++m_paintCount;
  // QPainter (the overlay) may leave state behind: reset what the passes below rely on.
  glDisable(GL_BLEND);
  glDisable(GL_SCISSOR_TEST);
  glDisable(GL_STENCIL_TEST);
  glDisable(GL_CULL_FACE);
  glClearColor(kBackgroundBottom.x(), kBackgroundBottom.y(), kBackgroundBottom.z(), 1.0f);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  drawBackground();
  if (m_meshProgram) {
    uploadIfDirty();
    drawMesh(m_wireframe);
  }
  drawOverlay();
}

void MeshViewport::uploadIfDirty() {
  const auto upload = [](QOpenGLBuffer& buffer, const auto& values) {
    buffer.bind();
    buffer.allocate(values.data(), static_cast<int>(values.size() * sizeof(values[0])));
    buffer.release();
  };
  if (m_vertexDataDirty) {
    upload(m_positionBuffer, m_positions);
    upload(m_normalBuffer, m_normals);
    m_vertexDataDirty = false;
  }
  if (m_tintsDirty) {
    upload(m_tintBuffer, m_tints);
    m_tintsDirty = false;
  }
  if (m_indicesDirty) {
    QOpenGLVertexArrayObject::Binder vaoBinder(&m_meshVao);
    m_indexBuffer.bind();  // stays bound: the element array binding is VAO state
    m_indexBuffer.allocate(m_indices.data(), static_cast<int>(m_indices.size() * sizeof(std::uint32_t)));
    m_indicesDirty = false;
  }
  if (m_restDirty && m_restBuffer.isCreated()) {
    upload(m_restBuffer, m_rest);
    m_restDirty = false;
  }
  if (m_basisDirty && m_basisBuffer != 0) {
    glBindBuffer(GL_TEXTURE_BUFFER, m_basisBuffer);
    glBufferData(GL_TEXTURE_BUFFER, static_cast<GLsizeiptr>(m_basis.size() * sizeof(float)), m_basis.data(),
                 GL_STATIC_DRAW);
    glBindBuffer(GL_TEXTURE_BUFFER, 0);
    m_basisDirty = false;
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

void MeshViewport::drawMesh(bool wireframe) {
  if (m_indices.empty()) {
    return;
  }
  wireframe = wireframe && m_gl33 != nullptr;
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LEQUAL);
  const QMatrix4x4 modelView = m_camera.view();
  const bool gpu = gpuDrawing();
  QOpenGLShaderProgram* program = gpu ? m_reconstructProgram.get() : m_meshProgram.get();
  program->bind();
  program->setUniformValue("uModelView", modelView);
  program->setUniformValue("uProjection", m_camera.projection());
  program->setUniformValue("uBaseColor", kMeshColor);
  program->setUniformValue("uLineColor", QVector4D(0, 0, 0, 0));
  if (gpu) {
    setGpuUniforms();
  } else {
    program->setUniformValue("uNormalMatrix", modelView.normalMatrix());
  }
  QOpenGLVertexArrayObject::Binder vaoBinder(gpu ? &m_gpuVao : &m_meshVao);
  const auto count = static_cast<GLsizei>(m_indices.size());
  // === fill pass, pushed back slightly so that the edges of the line pass win the depth test.
  if (wireframe) {
    glEnable(GL_POLYGON_OFFSET_FILL);
    glPolygonOffset(1.0f, 1.0f);
  }
  glDrawElements(GL_TRIANGLES, count, GL_UNSIGNED_INT, nullptr);
  glDisable(GL_POLYGON_OFFSET_FILL);
  // === line pass: the same triangles as edges.
  if (wireframe) {
    program->setUniformValue("uLineColor", kWireColor);
    m_gl33->glPolygonMode(GL_FRONT_AND_BACK, GL_LINE);
    glDrawElements(GL_TRIANGLES, count, GL_UNSIGNED_INT, nullptr);
    m_gl33->glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
  }
  if (gpu) {
    glBindTexture(GL_TEXTURE_BUFFER, 0);
  }
  program->release();
}

// QPainter over the GL picture: the brush outline and the drag hint. Skipped (no QPainter) when neither shows.
void MeshViewport::drawOverlay() {
  const bool brush =
      (m_tool == ViewportTool::HandleBrush || m_tool == ViewportTool::AnchorBrush) && m_cursor.has_value();
  if (!brush && m_visibleHint.isEmpty()) {
    return;
  }
  QPainter painter(this);
  painter.setRenderHint(QPainter::Antialiasing);
  if (brush) {
    const QColor color = m_tool == ViewportTool::HandleBrush ? QColor(255, 110, 60) : QColor(90, 150, 255);
    painter.setPen(QPen(color, 1.5));
    painter.setBrush(Qt::NoBrush);
    painter.drawEllipse(*m_cursor, m_brushRadius, m_brushRadius);
  }
  if (!m_visibleHint.isEmpty()) {
    QFont font = painter.font();
    font.setPointSizeF(font.pointSizeF() * 1.2);
    painter.setFont(font);
    const QRect text = painter.fontMetrics().boundingRect(m_visibleHint).adjusted(-12, -7, 12, 7);
    const QRect box(QPoint((width() - text.width()) / 2, height() - text.height() - 16), text.size());
    painter.setPen(Qt::NoPen);
    painter.setBrush(QColor(20, 20, 24, 200));
    painter.drawRoundedRect(box, 6, 6);
    painter.setPen(QColor(245, 245, 245));
    painter.drawText(box, Qt::AlignCenter, m_visibleHint);
  }
}

// Renders the mesh's depth into an offscreen, single-sampled framebuffer of the widget's device-pixel size and
// reads it back (the widget's own framebuffer is multisampled and cannot be read as depth).
DepthImage MeshViewport::renderDepth() {
  DepthImage image;
  if (!m_meshProgram || m_indices.empty() || context() == nullptr) {
    return image;
  }
  makeCurrent();
  const QSize size = (QSizeF(width(), height()) * devicePixelRatioF()).toSize();
  if (!m_pickFbo || m_pickFbo->size() != size) {
    m_pickFbo = std::make_unique<QOpenGLFramebufferObject>(size, QOpenGLFramebufferObject::Depth);
  }
  m_pickFbo->bind();
  glViewport(0, 0, size.width(), size.height());
  glClearDepthf(1.0f);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  uploadIfDirty();
  glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
  drawMesh(false);
  glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  image.width = size.width();
  image.height = size.height();
  image.depth.resize(static_cast<std::size_t>(size.width()) * static_cast<std::size_t>(size.height()));
  glPixelStorei(GL_PACK_ALIGNMENT, 4);
  glReadPixels(0, 0, size.width(), size.height(), GL_DEPTH_COMPONENT, GL_FLOAT, image.depth.data());
  m_pickFbo->release();
  doneCurrent();
  return image;
}

}  // namespace sc::app
