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
  m_sliceTimer.stop();
  m_picture.destroy();
  m_showingPartial = m_showingPicture = false;
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
  const bool large = window && drawsProgressively();
  const bool shown =
      large && !frame.proxy && !(frame.interactive && frame.moved) && showPicture(framebuffer, frame, scalable);
  if (window) {
    m_showingPartial = shown && !m_picture.complete();
    m_showingPicture = shown && !m_showingPartial;
    m_wholePictureShown = m_wholePictureShown || m_showingPicture || (!shown && !frame.proxy);
  }
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

bool MeshViewport::showPicture(unsigned framebuffer, FramePolicy::Frame& frame, bool scalable) {
  const ProgressivePicture::Key key = pictureKey();
  m_stages.start();
  if (!m_picture.completeFor(key) && !m_picture.drawing(key)) patchPicture(key);
  const double patchMs = m_stages.lap();
  const bool complete = m_picture.completeFor(key);
  // Without a proxy, once the window has shown this mesh whole (e.g. wireframe), a still paint draws the rest of the
  // picture, as it would the whole mesh, rather than show the slices so far; an interactive one (a resize) draws the
  // whole mesh, reduced, as before. A brush stroke's press completes the picture (renderDepth()).
  bool rest = false;
  if (!complete) {
    if (!m_picture.drawing(key)) m_picture.start(key, triangleCount());
    if (proxyMayDraw()) {
      m_sliceTimer.start();
      frame = m_policy.standIn(scalable);  // the proxy until the picture is complete
      return false;
    }
    rest = m_wholePictureShown && !frame.interactive;
    if (!rest) m_sliceTimer.start();
    if (m_wholePictureShown && !rest) return false;
  }
  m_stages.start();
  m_buffers.upload(*m_gl33, gpuBasis());
  m_frameTimes.uploadMs = m_stages.lap();
  if (rest || m_picture.slices() == 0) {
    m_picture.drawNext(*m_gl33, m_passes, m_buffers, m_frames.gpu(), meshPass(m_wireframe, false), rest);
  }
  m_picture.blit(*m_gl33, framebuffer);
  m_frameTimes.meshMs = patchMs + m_stages.lap();
  m_frameTimes.triangles = triangleCount();
  m_frameTimes.pictureSlices = m_picture.slices();
  return true;
}

bool MeshViewport::patchPicture(const ProgressivePicture::Key& key) {
  if (!m_picture.followsShape(key)) return false;
  m_buffers.upload(*m_gl33, gpuBasis());
  return m_picture.patchTints(*m_gl33, m_passes, m_buffers, m_frames.gpu(), meshPass(m_wireframe, false), key);
}

void MeshViewport::setProgressivePicture(int minimumTriangles, int sliceLimit) {
  m_progressiveMinimumTriangles = minimumTriangles;
  m_picture.setSliceLimit(sliceLimit);
  update();
}

QImage MeshViewport::progressivePictureImage() {
  if (!m_surface->makeContextCurrent()) return {};
  QImage image = m_picture.image().convertToFormat(QImage::Format_RGB32);
  doneCurrent();
  return image;
}

bool MeshViewport::progressivePictureCurrent() { return m_picture.completeFor(pictureKey()); }

bool MeshViewport::drawsProgressively() const {
  return m_policy.adaptive() && m_gl33 != nullptr && sampleCount() <= 0 && m_passes.meshReady() &&
         !pixelSize().isEmpty() && m_progressiveMinimumTriangles > 0 &&
         triangleCount() >= m_progressiveMinimumTriangles;
}

ProgressivePicture::Key MeshViewport::pictureKey() {
  m_frames.ensureFullVertexData(m_frameTimes);
  tightenBounds();
  return ProgressivePicture::key(m_buffers, meshPass(m_wireframe, false), pixelSize());
}

void MeshViewport::continuePicture() {
  if (!drawsProgressively()) {
    update();
    return;
  }
  const ProgressivePicture::Key key = pictureKey();
  if (m_picture.completeFor(key)) {
    if (!m_showingPicture) update();
    return;
  }
  if (m_picture.followsShape(key) && !m_picture.drawing(key)) {  // new tints: the paint patches the picture
    update();
    return;
  }
  if (!m_picture.drawing(key)) m_picture.start(key, triangleCount());
  m_sliceTimer.start();  // the window keeps its interactive frame until the picture is complete
}

void MeshViewport::drawPictureSlice() {
  if (!m_picture.drawing() || !drawsProgressively() || !m_surface->isExposed()) {
    return;
  }
  if (m_frames.fullVertexDataLagging()) {  // a newer frame: stale, and no reconstruction here to find out
    m_picture.reset();
    return;
  }
  if (!m_surface->makeContextCurrent()) return;
  const ProgressivePicture::Key key = pictureKey();
  if (!m_picture.drawing(key) && !patchPicture(key)) {  // changed (a gesture, frames): dropped until things are still
    m_picture.reset();
    doneCurrent();
    return;
  }
  m_buffers.upload(*m_gl33, gpuBasis());
  const bool complete = m_picture.drawNext(*m_gl33, m_passes, m_buffers, m_frames.gpu(), meshPass(m_wireframe, false));
  doneCurrent();
  if (complete || m_showingPartial) update();
  if (!complete) m_sliceTimer.start();
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
  // The picture of this shape and view (tints aside; without wireframe, whose fill is pushed back) has this depth: a
  // read-back instead of a pass over the whole mesh (0.4-0.6 s on llvmpipe at a million vertices). One that is not
  // complete (a stroke soon after an orbit) is completed here, for a little more than that pass (it shades too), and
  // shown; the paint after the dab then patches it instead of drawing the whole mesh again.
  if (!m_wireframe && drawsProgressively()) {
    const ProgressivePicture::Key key = pictureKey();
    const bool completing = !m_picture.shapeCompleteFor(key);
    if (completing) {
      if (!m_picture.drawing(key) && !patchPicture(key)) m_picture.start(key, triangleCount());
      m_buffers.upload(*m_gl33, gpuBasis());
      m_picture.drawNext(*m_gl33, m_passes, m_buffers, m_frames.gpu(), meshPass(false, false), true);
    }
    DepthImage image = m_picture.readDepth(*m_gl33);
    doneCurrent();
    if (completing) update();
    return image;
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
