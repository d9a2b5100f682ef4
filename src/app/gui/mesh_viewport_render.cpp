// MeshViewport, the GL side: the context's lifetime (hellogl2), the frame (FramePolicy's decision, the passes of
// ScenePasses into the widget or a reduced target, FrameTimes' GL stages), the depth read-back used for picking and
// the GPU path's read-back. The vertex data lives in ViewportBuffers, the GPU path's program in GpuReconstructor.

#include "app/gui/mesh_viewport.h"

#include "app/gui/viewport/lap_timer.h"
#include "app/gui/viewport/vertex_arrays.h"

#include <QOpenGLContext>
#include <QOpenGLFunctions_3_3_Core>
#include <QOpenGLVersionFunctionsFactory>

#include <algorithm>

namespace sc::app {

void MeshViewport::setSampleCount(int samples) {
  QSurfaceFormat f = format();
  f.setSamples(std::max(0, samples));
  setFormat(f);
}

void MeshViewport::cleanup() {
  if (!m_passes.created()) {
    return;
  }
  makeCurrent();
  m_glReady = false;
  if (m_gl33 != nullptr) {
    m_gpu.destroy(*m_gl33);
    m_buffers.destroy(*m_gl33);
  }
  m_passes.destroy();
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
  if (m_gl33 == nullptr || !m_passes.create()) {
    return;  // the passes need OpenGL 3.3 core: background only, or nothing
  }
  // A new context has empty buffers: create() marks whatever the host side holds for upload.
  m_buffers.create(*m_gl33, m_gpu.create(*m_gl33));
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
  // Interactive frames (a paint shortly after the previous one) may be drawn at a reduced resolution, or as the
  // interactive proxy; their paint is finished and measured (the rasteriser's time belongs to the measurement).
  const bool scalable = m_policy.adaptive() && m_gl33 != nullptr && format().samples() <= 0;
  const FramePolicy::Frame frame = m_policy.begin(scalable, proxyMayDraw());
  if (!frame.proxy) {
    ensureFullVertexData();
  }
  QElapsedTimer paint;
  paint.start();
  drawScene(frame);
  if (m_policy.end(frame, static_cast<double>(paint.nsecsElapsed()) * 1e-6)) {
    m_restoreTimer.start();
  }
  QElapsedTimer overlay;
  overlay.start();
  m_input.paintOverlay();
  endStage(m_frameTimes.overlayMs, overlay);
  m_frameTimes.renderScale = frame.scale;
  m_policy.painted();  // from the end of this paint: a slow frame does not make the next one idle
}

// Ends one FrameTimes stage: the stage hook (e.g. the benchmark's glFinish()), then the stage's time.
void MeshViewport::endStage(double& ms, QElapsedTimer& timer) {
  if (m_stageHook) {
    m_stageHook();
  }
  ms = lapMs(timer);
}

MeshPass MeshViewport::meshPass(bool wireframe, bool proxy) const {
  return {m_camera.view(), m_camera.projection(), wireframe, proxy, gpuDrawing() ? &m_shown.Z() : nullptr};
}

// Upload, background and mesh passes into the widget's framebuffer, or at a scale < 1 into a reduced target that
// is then stretched onto it (the mesh pass's time includes that blit). Fills the GL stages of m_frameTimes. A proxy
// frame's mesh pass draws the interactive proxy; a scalable frame ends with glFinish().
void MeshViewport::drawScene(const FramePolicy::Frame& frame) {
  m_frameTimes.uploadMs = m_frameTimes.backgroundMs = m_frameTimes.meshMs = 0.0;
  m_frameTimes.triangles = 0;
  if (m_gl33 == nullptr) {
    return;
  }
  QElapsedTimer timer;
  timer.start();
  if (m_passes.meshReady()) {
    m_buffers.upload(*m_gl33, gpuDrawing() ? &m_shown.K() : nullptr);
    endStage(m_frameTimes.uploadMs, timer);
  }
  const QSize full = (QSizeF(width(), height()) * devicePixelRatioF()).toSize();
  const QSize reduced = (QSizeF(full) * frame.scale).toSize().expandedTo(QSize(1, 1));
  const bool offscreen = frame.scale < 1.0 && reduced != full;
  if (offscreen) {
    m_passes.beginReduced(*m_gl33, reduced);
  }
  m_passes.drawBackground(*m_gl33);
  endStage(m_frameTimes.backgroundMs, timer);
  m_frameTimes.triangles = m_passes.drawMesh(*m_gl33, m_buffers, m_gpu, meshPass(m_wireframe, frame.proxy));
  if (offscreen) {
    m_passes.endReduced(*m_gl33, defaultFramebufferObject(), reduced, full);
  }
  if (frame.scalable) {
    glFinish();
  }
  endStage(m_frameTimes.meshMs, timer);
}

DepthImage MeshViewport::renderDepth() {
  if (!m_passes.meshReady() || m_buffers.indices().empty() || context() == nullptr || m_gl33 == nullptr) {
    return {};
  }
  makeCurrent();
  ensureFullVertexData();
  m_buffers.upload(*m_gl33, gpuDrawing() ? &m_shown.K() : nullptr);
  const QSize size = (QSizeF(width(), height()) * devicePixelRatioF()).toSize();
  DepthImage image = m_passes.renderDepth(*m_gl33, size, m_buffers, m_gpu, meshPass(false, false));
  doneCurrent();
  return image;
}

std::vector<float> MeshViewport::gpuReconstructedPositions() {
  if (!m_glReady || m_shown.empty() || !gpuReconstructionAvailable() || context() == nullptr) {
    return {};
  }
  makeCurrent();
  m_buffers.upload(*m_gl33, &m_shown.K());
  const std::vector<float> shaded =
      m_gpu.readBack(*m_gl33, m_buffers.gpuVao(), m_buffers.basisTexture(), m_shown.Z(), m_vertexCount);
  doneCurrent();
  std::vector<float> xyz;
  shifted(shaded, m_origin, xyz);
  return xyz;
}

}  // namespace sc::app
