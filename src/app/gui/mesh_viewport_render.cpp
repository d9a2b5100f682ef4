// MeshViewport, the GL side: the surface's context lifetime (hellogl2), the paint (FramePolicy's decision, then
// ScenePasses::drawFrame() and the overlays) on the window or offscreen (grabFramebuffer()), the depth read-back used
// for picking and the GPU path's read-back. The vertex data lives in ViewportBuffers, the GPU path's program in
// GpuReconstructor.

#include "app/gui/mesh_viewport.h"

#include "app/gui/viewport/lap_timer.h"
#include "app/gui/viewport/vertex_arrays.h"

#include <QOpenGLContext>
#include <QOpenGLFramebufferObject>
#include <QOpenGLFunctions_3_3_Core>
#include <QOpenGLPaintDevice>
#include <QOpenGLVersionFunctionsFactory>
#include <QPainter>

#include <algorithm>

namespace sc::app {

void MeshViewport::setSampleCount(int samples) {
  QSurfaceFormat f = m_surface->requestedFormat();
  f.setSamples(std::max(0, samples));
  m_surface->setFormat(f);
}

void MeshViewport::update() {
  ++m_repaintRequests;
  m_surface->update();
}

void MeshViewport::repaint() {
  ++m_repaintRequests;
  m_surface->paintNow();
}

void MeshViewport::makeCurrent() { m_surface->makeContextCurrent(); }

void MeshViewport::doneCurrent() { m_surface->doneCurrent(); }

QImage MeshViewport::grabFramebuffer() {
  // The first call may create the context and run initializeSurface(); never shown: no context to draw with.
  if (!m_surface->makeContextCurrent() || pixelSize().isEmpty()) {
    return {};
  }
  QOpenGLFramebufferObjectFormat format;
  format.setAttachment(QOpenGLFramebufferObject::CombinedDepthStencil);
  format.setSamples(std::max(0, sampleCount()));
  QOpenGLFramebufferObject target(pixelSize(), format);
  target.bind();
  paint(target.handle(), false);
  QImage image = target.toImage().convertToFormat(QImage::Format_RGB32);
  image.setDevicePixelRatio(devicePixelRatioF());
  target.release();
  doneCurrent();
  return image;
}

void MeshViewport::cleanup() {
  if (!m_passes.created()) {
    return;
  }
  makeCurrent();
  m_frames.setGlReady(false);
  m_pictures.destroy();
  if (m_gl33 != nullptr) {
    m_frames.gpu().destroy(*m_gl33);
    m_buffers.destroy(*m_gl33);
  }
  m_passes.destroy();
  m_gl33 = nullptr;
  doneCurrent();
  if (context() != nullptr) {
    QObject::disconnect(context(), &QOpenGLContext::aboutToBeDestroyed, this, &MeshViewport::cleanup);
  }
}

void MeshViewport::initializeSurface() {
  // Release our objects when the context goes (the window's platform surface is destroyed), and re-create them
  // here when a new context follows (hellogl2).
  connect(context(), &QOpenGLContext::aboutToBeDestroyed, this, &MeshViewport::cleanup);
  initializeOpenGLFunctions();
  m_gl33 = QOpenGLVersionFunctionsFactory::get<QOpenGLFunctions_3_3_Core>(context());
  if (m_gl33 == nullptr || !m_passes.create()) {
    return;  // the passes need OpenGL 3.3 core: background only, or nothing
  }
  // A new context has empty buffers: create() marks whatever the host side holds for upload.
  m_buffers.create(*m_gl33, m_frames.gpu().create(*m_gl33));
  m_frames.setGlReady(true);
  setReconstructionPath(m_frames.path());  // falls back to the CPU path if this context cannot draw the basis
}

void MeshViewport::resizeSurface(int width, int height) { m_camera.setViewportSize(width, height); }

void MeshViewport::paintSurface(unsigned framebuffer) { paint(framebuffer, true); }

void MeshViewport::paint(unsigned framebuffer, bool window) {
  ++m_paintCount;
  // The whole target (the window's paint sets this too; a grab's framebuffer may follow a resize without one).
  glViewport(0, 0, pixelSize().width(), pixelSize().height());
  // QPainter (the overlay) may leave state behind: reset what the passes below rely on.
  glDisable(GL_BLEND);
  glDisable(GL_SCISSOR_TEST);
  glDisable(GL_STENCIL_TEST);
  glDisable(GL_CULL_FACE);
  // Interactive frames (a paint shortly after the previous one) may be drawn at a reduced resolution, or as the
  // interactive proxy; their paint is finished and measured (the rasteriser's time belongs to the measurement).
  const bool scalable = m_policy.adaptive() && m_gl33 != nullptr && sampleCount() <= 0;
  FramePolicy::Frame frame = m_policy.begin(scalable, proxyMayDraw());
  if (!frame.proxy) {
    m_frames.ensureFullVertexData(m_frameTimes);
    tightenBounds();
  }
  QElapsedTimer paintClock;
  paintClock.start();
  m_frameTimes.uploadMs = m_frameTimes.backgroundMs = m_frameTimes.meshMs = 0.0;
  m_frameTimes.triangles = 0;
  m_frameTimes.pictureSlices = 0;
  // A still (or idle) picture of a large mesh comes from the progressive picture; a moving frame without the proxy
  // draws the whole mesh as before (reduced), since a picture restarted every frame would show only its first slice.
  const bool large = window && m_pictures.active();
  PicturePresenter::Paint picture = PicturePresenter::Paint::Whole;
  if (large && !frame.proxy && !(frame.interactive && frame.moved)) {
    picture = m_pictures.show(framebuffer, frame.interactive, m_stages, m_frameTimes);
    if (picture == PicturePresenter::Paint::Proxy) frame = m_policy.standIn(scalable);  // until the picture is complete
  }
  const bool shown = picture == PicturePresenter::Paint::Picture;
  if (window) m_pictures.windowPainted(shown, frame.proxy);
  if (m_gl33 != nullptr && !shown) {
    m_passes.drawFrame(*m_gl33, m_buffers, m_frames.gpu(), gpuBasis(), meshPass(m_wireframe, frame.proxy),
                       {framebuffer, pixelSize(), frame.scale, frame.scalable}, m_stages, m_frameTimes);
    // Once idle, a reduced or proxy frame is followed by a full one; a large mesh's full picture is then drawn in
    // slices (continuePicture()) even after a full-resolution moving frame, so that a still paint can show it.
    if (m_policy.end(frame, static_cast<double>(paintClock.nsecsElapsed()) * 1e-6) || large) {
      m_restoreTimer.start();
    }
  }
  m_stages.start();
  if (m_input.overlayShown() || !m_presence.markers().empty()) {
    // QPainter through a paint device over the bound framebuffer (the window's or the grab's); it changes GL state,
    // which the next paint resets.
    glBindFramebuffer(GL_FRAMEBUFFER, framebuffer);
    QOpenGLPaintDevice device(pixelSize());
    device.setDevicePixelRatio(devicePixelRatioF());
    QPainter painter(&device);
    m_input.paintOverlay(painter, size());
    if (!m_presence.markers().empty()) {
      m_presence.paint(painter, m_camera.view(), m_camera.projection(), size(), m_sceneDiagonal);
    }
  }
  m_frameTimes.overlayMs = m_stages.lap();
  m_frameTimes.renderScale = frame.scale;
  m_policy.painted();  // from the end of this paint: a slow frame does not make the next one idle
}

void MeshViewport::setProgressivePicture(int minimumTriangles, int sliceLimit) {
  m_pictures.setMinimumTriangles(minimumTriangles, sliceLimit);
  update();
}

QImage MeshViewport::progressivePictureImage() {
  if (!m_surface->makeContextCurrent()) return {};
  QImage image = m_pictures.picture().image().convertToFormat(QImage::Format_RGB32);
  doneCurrent();
  return image;
}

bool MeshViewport::picturesPossible() const {
  return m_policy.adaptive() && m_gl33 != nullptr && sampleCount() <= 0 && m_passes.meshReady() &&
         !pixelSize().isEmpty();
}

ProgressivePicture::Key MeshViewport::currentPictureKey() {
  m_frames.ensureFullVertexData(m_frameTimes);
  tightenBounds();
  return ProgressivePicture::key(m_buffers, meshPass(m_wireframe, false), pixelSize());
}

PictureScene MeshViewport::pictureScene() {
  m_buffers.upload(*m_gl33, gpuBasis());
  return {*m_gl33, m_passes, m_buffers, m_frames.gpu(), meshPass(m_wireframe, false)};
}

QSize MeshViewport::pixelSize() const { return (QSizeF(width(), height()) * devicePixelRatioF()).toSize(); }

const spectral::QuantizedBasis* MeshViewport::gpuBasis() const {
  return m_frames.gpuDrawing() ? &m_frames.shown().K() : nullptr;
}

MeshPass MeshViewport::meshPass(bool wireframe, bool proxy) const {
  return {m_camera.view(), m_camera.projection(), wireframe, proxy,
          m_frames.gpuDrawing() ? &m_frames.shown().scaledZ() : nullptr};
}

DepthImage MeshViewport::renderDepth() {
  if (!m_passes.meshReady() || m_buffers.indices().empty() || context() == nullptr || m_gl33 == nullptr) {
    return {};
  }
  makeCurrent();
  // Without wireframe (whose fill is pushed back), a large mesh's picture has this depth (PicturePresenter).
  if (!m_wireframe) {
    if (std::optional<DepthImage> image = m_pictures.depthForPicking()) {
      doneCurrent();
      return *std::move(image);
    }
  }
  m_frames.ensureFullVertexData(m_frameTimes);
  m_buffers.upload(*m_gl33, gpuBasis());
  DepthImage image = m_passes.renderDepth(*m_gl33, pixelSize(), m_buffers, m_frames.gpu(), meshPass(false, false));
  doneCurrent();
  return image;
}

std::vector<float> MeshViewport::gpuReconstructedPositions() {
  if (!hasReconstructionBasis() || !gpuReconstructionAvailable() || context() == nullptr) {
    return {};
  }
  const ShownLevel& shown = m_frames.shown();
  makeCurrent();
  m_buffers.upload(*m_gl33, &shown.K());
  const std::vector<float> shaded =
      m_frames.gpu().readBack(*m_gl33, m_buffers.gpuVao(), m_buffers.basisTexture(), shown.scaledZ(), m_vertexCount);
  doneCurrent();
  std::vector<float> xyz;
  shifted(shaded, m_origin, xyz);
  return xyz;
}

}  // namespace sc::app
