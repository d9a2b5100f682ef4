#include "app/gui/viewport/progressive_picture.h"

#include "app/gui/viewport/viewport_buffers.h"

#include <QElapsedTimer>
#include <QImage>
#include <QOpenGLFramebufferObject>
#include <QOpenGLFunctions_3_3_Core>

#include <algorithm>
#include <cstring>
#include <span>
#include <utility>

namespace sc::app {

namespace {
/// Bounds on a slice: a few thousand triangles cost less than a slice's fixed work (bind, clear state, glFinish).
constexpr int kMinimumSliceTriangles = 4096;
}  // namespace

ProgressivePicture::Key ProgressivePicture::key(const ViewportBuffers& buffers, const MeshPass& pass, QSize size) {
  Key key;
  key.shared = buffers.sharedVersion();
  key.tints = buffers.tintVersion();
  key.vertices = pass.gpuZ == nullptr ? buffers.vertexVersion() : 0;
  key.view = pass.view;
  key.projection = pass.projection;
  key.size = size;
  key.wireframe = pass.wireframe;
  if (pass.gpuZ != nullptr) key.gpuZ = *pass.gpuZ;
  return key;
}

ProgressivePicture::ProgressivePicture() = default;
ProgressivePicture::~ProgressivePicture() = default;

void ProgressivePicture::start(Key key, int triangles) {
  m_key = std::move(key);
  m_started = true;
  m_complete = false;
  m_triangles = std::max(0, triangles);
  m_next = 0;
  m_slices = 0;
}

void ProgressivePicture::reset() {
  m_started = false;
  m_complete = false;
  m_slices = 0;
}

void ProgressivePicture::bindTarget(QOpenGLFunctions_3_3_Core& gl) {
  m_target->bind();
  gl.glViewport(0, 0, m_key.size.width(), m_key.size.height());
  gl.glDisable(GL_BLEND);
  gl.glDisable(GL_SCISSOR_TEST);
  gl.glDisable(GL_STENCIL_TEST);
  gl.glDisable(GL_CULL_FACE);
}

bool ProgressivePicture::drawNext(QOpenGLFunctions_3_3_Core& gl, ScenePasses& passes, ViewportBuffers& buffers,
                                  GpuReconstructor& gpu, MeshPass pass, bool rest) {
  if (!m_started || m_complete) return m_complete;
  QElapsedTimer clock;
  clock.start();
  if (!m_target || m_target->size() != m_key.size) {
    m_target = std::make_unique<QOpenGLFramebufferObject>(m_key.size, QOpenGLFramebufferObject::Depth);
  }
  bindTarget(gl);
  if (m_next == 0) {
    passes.drawBackground(gl);
    m_tints = buffers.tints();
  }
  const int planned =
      rest ? m_triangles - m_next : (m_sliceLimit > 0 ? std::min(m_sliceTriangles, m_sliceLimit) : m_sliceTriangles);
  const int slice = std::min(planned, m_triangles - m_next);
  pass.proxy = false;
  pass.firstTriangle = m_next;
  pass.triangleCount = slice;
  passes.drawMesh(gl, buffers, gpu, pass);
  gl.glFinish();
  m_target->release();
  m_next += slice;
  ++m_slices;
  const double ms = static_cast<double>(clock.nsecsElapsed()) * 1e-6;
  // the next slice at this one's rate, at most twice as large
  if (!rest && slice == planned && slice > 0 && ms > 0.0) {
    const double fitting = static_cast<double>(slice) * kSliceBudgetMs / ms;
    m_sliceTriangles = static_cast<int>(std::clamp(fitting, static_cast<double>(kMinimumSliceTriangles),
                                                   2.0 * std::max(slice, kMinimumSliceTriangles)));
  }
  if (m_next >= m_triangles) {
    m_complete = true;
    ++m_completed;
  }
  return m_complete;
}

bool ProgressivePicture::patchTints(QOpenGLFunctions_3_3_Core& gl, ScenePasses& passes, ViewportBuffers& buffers,
                                    GpuReconstructor& gpu, MeshPass pass, const Key& key) {
  if (m_started && m_key == key) return true;
  if (!followsShape(key) || key.wireframe) return false;
  if (m_next == 0 || !m_target) {  // nothing drawn yet: the first slice draws the new tints
    m_key = key;
    return true;
  }
  const std::vector<std::uint8_t>& tints = buffers.tints();
  if (tints.size() != m_tints.size()) return false;
  constexpr std::size_t kTint = 4;  // RGBA bytes per vertex
  const std::size_t vertices = tints.size() / kTint;
  m_changed.assign(vertices, 0);
  bool any = false;
  for (std::size_t v = 0; v < vertices; ++v) {
    if (std::memcmp(&tints[kTint * v], &m_tints[kTint * v], kTint) != 0) m_changed[v] = any = 1;
  }
  std::vector<std::uint32_t> patch;
  if (any) {
    const std::span<const std::uint32_t> indices = buffers.indices().first(
        std::min(buffers.indices().size(), 3 * static_cast<std::size_t>(m_next)));  // the slices drawn so far
    const std::size_t limit = indices.size() / 4;
    for (std::size_t i = 0; i + 2 < indices.size(); i += 3) {
      const std::uint32_t a = indices[i], b = indices[i + 1], c = indices[i + 2];
      if (std::max({a, b, c}) >= vertices) return false;  // cannot happen for a drawn mesh; the picture stays
      if ((m_changed[a] | m_changed[b] | m_changed[c]) == 0) continue;
      if (patch.size() >= limit) return false;
      patch.insert(patch.end(), {a, b, c});
    }
  }
  if (!patch.empty()) {
    buffers.uploadPatch(patch);
    bindTarget(gl);
    pass.proxy = false;
    pass.patch = true;
    passes.drawMesh(gl, buffers, gpu, pass);  // depth test GL_LEQUAL: a redrawn front triangle wins its pixels
    m_target->release();
  }
  m_tints = tints;
  m_key = key;
  ++m_patches;
  return true;
}

void ProgressivePicture::blit(QOpenGLFunctions_3_3_Core& gl, unsigned target) const {
  if (!m_target) return;
  const QSize size = m_target->size();
  gl.glBindFramebuffer(GL_READ_FRAMEBUFFER, m_target->handle());
  gl.glBindFramebuffer(GL_DRAW_FRAMEBUFFER, target);
  gl.glBlitFramebuffer(0, 0, size.width(), size.height(), 0, 0, size.width(), size.height(), GL_COLOR_BUFFER_BIT,
                       GL_NEAREST);
  gl.glBindFramebuffer(GL_FRAMEBUFFER, target);
}

DepthImage ProgressivePicture::readDepth(QOpenGLFunctions_3_3_Core& gl) const {
  DepthImage image;
  if (!m_complete || !m_target) return image;
  image.width = m_target->width();
  image.height = m_target->height();
  image.depth.resize(static_cast<std::size_t>(image.width) * static_cast<std::size_t>(image.height));
  m_target->bind();
  gl.glPixelStorei(GL_PACK_ALIGNMENT, 4);
  gl.glReadPixels(0, 0, image.width, image.height, GL_DEPTH_COMPONENT, GL_FLOAT, image.depth.data());
  m_target->release();
  ++m_depthReads;
  return image;
}

QImage ProgressivePicture::image() const { return m_target ? m_target->toImage() : QImage(); }

void ProgressivePicture::destroy() {
  m_target.reset();
  reset();
}

}  // namespace sc::app
