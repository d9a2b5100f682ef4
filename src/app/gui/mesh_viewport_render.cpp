// MeshViewport, the GL side: surface format and sample count, context resources (programs; the vertex arrays and
// buffer uploads are in mesh_viewport_buffers.cpp), the background and shaded/wireframe passes and the depth
// read-back used for picking.

#include "app/gui/mesh_viewport.h"

#include "app/gui/mesh_shaders.h"

#include <QOffscreenSurface>
#include <QOpenGLContext>
#include <QOpenGLFramebufferObject>
#include <QOpenGLFunctions_3_3_Core>
#include <QOpenGLShaderProgram>
#include <QOpenGLVersionFunctionsFactory>

#include <algorithm>

namespace sc::app {

namespace {

const QVector3D kBackgroundTop{0.40f, 0.44f, 0.51f};
const QVector3D kBackgroundBottom{0.11f, 0.12f, 0.15f};
const QVector3D kMeshColor{0.76f, 0.70f, 0.62f};  // warm clay
const QVector4D kWireColor{0.16f, 0.14f, 0.13f, 1.0f};

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

namespace {

// Whether the default format's renderer is a software rasteriser (probed once per process).
bool softwareRenderer() {
  static const bool software = [] {
    const QString renderer = MeshViewport::rendererName().toLower();
    return renderer.contains(QLatin1String("llvmpipe")) || renderer.contains(QLatin1String("softpipe")) ||
           renderer.contains(QLatin1String("software"));
  }();
  return software;
}

// $name as an integer ≥ 0, or `otherwise` when unset or not an integer.
int environmentOr(const char* name, int otherwise) {
  bool ok = false;
  const int value = qEnvironmentVariableIntValue(name, &ok);
  return ok ? std::max(0, value) : otherwise;
}

}  // namespace

int MeshViewport::defaultSampleCount() {
  static const int samples = environmentOr("SHAPECAST_MSAA", softwareRenderer() ? 0 : 4);
  return samples;
}

ReconstructionPath MeshViewport::defaultReconstructionPath() {
  static const ReconstructionPath path = [] {
    const QByteArray chosen = qgetenv("SHAPECAST_RECONSTRUCTION").toLower();
    if (chosen == "cpu" || chosen == "gpu") {
      return chosen == "gpu" ? ReconstructionPath::Gpu : ReconstructionPath::Cpu;
    }
    return softwareRenderer() ? ReconstructionPath::Cpu : ReconstructionPath::Gpu;
  }();
  return path;
}

bool MeshViewport::defaultAdaptiveResolution() {
  static const bool adaptive = environmentOr("SHAPECAST_ADAPTIVE_RESOLUTION", softwareRenderer() ? 1 : 0) != 0;
  return adaptive;
}

void MeshViewport::setAdaptiveResolution(bool on) {
  m_adaptive = on;
  m_resolution.reset();
  m_proxyResolution.reset();
  update();
}

void MeshViewport::setSampleCount(int samples) {
  QSurfaceFormat f = format();
  f.setSamples(std::max(0, samples));
  setFormat(f);
}

void MeshViewport::cleanup() {
  if (!m_meshProgram && !m_backgroundProgram && !m_meshVao.isCreated()) {
    return;
  }
  makeCurrent();
  m_glReady = false;
  destroyGpuObjects();
  m_pickFbo.reset();
  m_sceneFbo.reset();
  for (QOpenGLBuffer* buffer :
       {&m_positionBuffer, &m_normalBuffer, &m_tintBuffer, &m_indexBuffer, &m_proxyPositionBuffer, &m_proxyNormalBuffer,
        &m_proxyTintBuffer, &m_proxyIndexBuffer}) {
    buffer->destroy();
  }
  m_meshVao.destroy();
  m_proxyVao.destroy();
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
  if (!m_meshProgram) {
    return;
  }

  createMeshVaos();
  createGpuObjects();

  // A new context has empty buffers: upload whatever the host side holds.
  m_vertexDataDirty = true;
  m_tintsDirty = true;
  m_indicesDirty = true;
  m_proxyDataDirty = true;
  m_proxyTintsDirty = true;
  m_proxyIndicesDirty = true;
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
  // Interactive (a paint shortly after the previous one) frames may be drawn at a reduced resolution.
  const bool interactive = m_sinceLastPaint.isValid() && m_sinceLastPaint.elapsed() < kIdleRestoreMs;
  const bool scalable = m_adaptive && m_gl33 != nullptr && format().samples() <= 0;
  const bool proxy = interactive && scalable && proxyAllowed();
  if (!proxy) {
    ensureFullVertexData();
  }
  AdaptiveResolution& resolution = proxy ? m_proxyResolution : m_resolution;
  const double scale = interactive && scalable ? resolution.scale() : 1.0;
  m_moved = false;
  QElapsedTimer paint;
  paint.start();
  drawScene(scale, proxy, scalable);  // finished when scalable: the rasteriser's time belongs to the measurement
  if (scalable) {
    resolution.record(scale, static_cast<double>(paint.nsecsElapsed()) * 1e-6);
  }
  if (scale < 1.0 || proxy) {
    m_restoreTimer.start();
  }
  QElapsedTimer overlay;
  overlay.start();
  drawOverlay();
  if (m_profiling) {
    glFinish();
  }
  m_frameTimes.overlayMs = lapMs(overlay);
  m_frameTimes.renderScale = scale;
  m_sinceLastPaint.start();  // from the end of this paint: a slow frame does not make the next one idle
}

// Whether an interactive frame of a moving shape may draw the interactive proxy (see setInteractiveProxy()).
bool MeshViewport::proxyMayDraw() const {
  return m_adaptive && format().samples() <= 0 && !m_proxyIndices.empty() && !m_wireframe &&
         m_gesture != Gesture::Paint && m_proxyShowsSelection;
}

// Whether this frame may draw the interactive proxy (the caller checks interactivity).
bool MeshViewport::proxyAllowed() const { return m_moved && proxyMayDraw(); }

// Upload, background and mesh passes into the widget's framebuffer, or at `scale` < 1 into m_sceneFbo that is
// then stretched onto it (the mesh pass's time includes that blit). Fills the GL stages of m_frameTimes. `proxy`:
// the mesh pass draws the interactive proxy. `finish`: glFinish() at the end.
void MeshViewport::drawScene(double scale, bool proxy, bool finish) {
  QElapsedTimer timer;
  timer.start();
  // Ends one FrameTimes stage (with glFinish() when profiling).
  const auto stage = [this, &timer](double& ms) {
    if (m_profiling) {
      glFinish();
    }
    ms = lapMs(timer);
  };
  m_frameTimes.uploadMs = m_frameTimes.meshMs = 0.0;
  if (m_meshProgram) {
    uploadIfDirty();
    stage(m_frameTimes.uploadMs);
  }
  const QSize full = (QSizeF(width(), height()) * devicePixelRatioF()).toSize();
  const QSize reduced = (QSizeF(full) * scale).toSize().expandedTo(QSize(1, 1));
  const bool offscreen = scale < 1.0 && reduced != full;
  if (offscreen) {
    if (!m_sceneFbo || m_sceneFbo->size() != reduced) {
      m_sceneFbo = std::make_unique<QOpenGLFramebufferObject>(reduced, QOpenGLFramebufferObject::Depth);
    }
    m_sceneFbo->bind();
    glViewport(0, 0, reduced.width(), reduced.height());
  }
  glClearColor(kBackgroundBottom.x(), kBackgroundBottom.y(), kBackgroundBottom.z(), 1.0f);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  drawBackground();
  stage(m_frameTimes.backgroundMs);
  m_frameTimes.triangles = m_meshProgram ? drawMesh(m_wireframe, proxy) : 0;
  if (offscreen) {
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, defaultFramebufferObject());
    m_gl33->glBlitFramebuffer(0, 0, reduced.width(), reduced.height(), 0, 0, full.width(), full.height(),
                              GL_COLOR_BUFFER_BIT, GL_LINEAR);
    glBindFramebuffer(GL_FRAMEBUFFER, defaultFramebufferObject());
    glViewport(0, 0, full.width(), full.height());
  }
  if (finish) {
    glFinish();
  }
  stage(m_frameTimes.meshMs);
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

// Draws the mesh's triangles, or with `proxy` those of the interactive proxy (on the GPU path after them in
// m_indexBuffer, otherwise from the compact proxy's VAO). Returns the number of triangles drawn.
int MeshViewport::drawMesh(bool wireframe, bool proxy) {
  if (m_indices.empty()) {
    return 0;
  }
  proxy = proxy && !m_proxyIndices.empty();
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
  const bool compact = proxy && !gpu;
  QOpenGLVertexArrayObject::Binder vaoBinder(gpu ? &m_gpuVao : compact ? &m_proxyVao : &m_meshVao);
  const auto count = static_cast<GLsizei>(proxy ? m_proxyIndices.size() : m_indices.size());
  const auto* first = reinterpret_cast<const void*>(proxy && gpu ? m_indices.size() * sizeof(std::uint32_t) : 0);
  // === fill pass, pushed back slightly so that the edges of the line pass win the depth test.
  if (wireframe) {
    glEnable(GL_POLYGON_OFFSET_FILL);
    glPolygonOffset(1.0f, 1.0f);
  }
  glDrawElements(GL_TRIANGLES, count, GL_UNSIGNED_INT, first);
  glDisable(GL_POLYGON_OFFSET_FILL);
  // === line pass: the same triangles as edges.
  if (wireframe) {
    program->setUniformValue("uLineColor", kWireColor);
    m_gl33->glPolygonMode(GL_FRONT_AND_BACK, GL_LINE);
    glDrawElements(GL_TRIANGLES, count, GL_UNSIGNED_INT, first);
    m_gl33->glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
  }
  if (gpu) {
    glBindTexture(GL_TEXTURE_BUFFER, 0);
  }
  program->release();
  return count / 3;
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
  ensureFullVertexData();
  uploadIfDirty();
  glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
  drawMesh(false, false);
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
