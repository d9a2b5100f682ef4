#include "app/gui/viewport/scene_passes.h"

#include "app/gui/mesh_shaders.h"
#include "app/gui/viewport/gpu_reconstructor.h"
#include "app/gui/viewport/lap_timer.h"
#include "app/gui/viewport/viewport_buffers.h"

#include <QOpenGLFramebufferObject>
#include <QOpenGLFunctions_3_3_Core>
#include <QOpenGLShaderProgram>

#include <algorithm>
#include <cstddef>
#include <span>

namespace sc::app {

namespace {

const QVector3D kBackgroundTop{0.40f, 0.44f, 0.51f};
const QVector3D kBackgroundBottom{0.11f, 0.12f, 0.15f};
const QVector3D kMeshColor{0.76f, 0.70f, 0.62f};  // warm clay
const QVector4D kWireColor{0.16f, 0.14f, 0.13f, 1.0f};

}  // namespace

ScenePasses::ScenePasses() = default;
ScenePasses::~ScenePasses() = default;

bool ScenePasses::create() {
  m_backgroundProgram = shaders::makeProgram(shaders::kBackgroundVertex, shaders::kBackgroundFragment);
  m_meshProgram = shaders::makeProgram(shaders::kMeshVertex, shaders::kMeshFragment);
  m_backgroundVao.create();
  return m_meshProgram != nullptr;
}

void ScenePasses::destroy() {
  m_pickFbo.reset();
  m_sceneFbo.reset();
  m_backgroundVao.destroy();
  m_meshProgram.reset();
  m_backgroundProgram.reset();
}

void ScenePasses::drawBackground(QOpenGLFunctions_3_3_Core& gl) {
  gl.glClearColor(kBackgroundBottom.x(), kBackgroundBottom.y(), kBackgroundBottom.z(), 1.0f);
  gl.glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  if (!m_backgroundProgram) {
    return;
  }
  gl.glDisable(GL_DEPTH_TEST);
  gl.glDepthMask(GL_FALSE);
  m_backgroundProgram->bind();
  m_backgroundProgram->setUniformValue("uTopColor", kBackgroundTop);
  m_backgroundProgram->setUniformValue("uBottomColor", kBackgroundBottom);
  QOpenGLVertexArrayObject::Binder vaoBinder(&m_backgroundVao);
  gl.glDrawArrays(GL_TRIANGLES, 0, 3);
  m_backgroundProgram->release();
  gl.glDepthMask(GL_TRUE);
}

void ScenePasses::drawFrame(QOpenGLFunctions_3_3_Core& gl, ViewportBuffers& buffers, GpuReconstructor& gpu,
                            const spectral::QuantizedBasis* K, const MeshPass& pass, const FrameTarget& target,
                            StageClock& clock, FrameTimes& times) {
  clock.start();
  times.uploadMs = 0.0;
  if (meshReady()) {
    buffers.upload(gl, K);
    times.uploadMs = clock.lap();
  }
  const QSize reduced = (QSizeF(target.full) * target.scale).toSize().expandedTo(QSize(1, 1));
  const bool offscreen = target.scale < 1.0 && reduced != target.full;
  if (offscreen) {
    beginReduced(gl, reduced);
  }
  drawBackground(gl);
  times.backgroundMs = clock.lap();
  times.triangles = drawMesh(gl, buffers, gpu, pass);
  if (offscreen) {
    endReduced(gl, target.framebuffer, reduced, target.full);
  }
  if (target.finish) {
    gl.glFinish();
  }
  times.meshMs = clock.lap();
}

// The mesh's triangles, or with pass.proxy those of the interactive proxy (on the GPU path after them in the mesh's
// index buffer, otherwise from the compact proxy's VAO).
int ScenePasses::drawMesh(QOpenGLFunctions_3_3_Core& gl, ViewportBuffers& buffers, GpuReconstructor& gpu,
                          const MeshPass& pass) {
  const std::span<const std::uint32_t> indices = buffers.indices();
  if (indices.empty() || !m_meshProgram) {
    return 0;
  }
  const bool proxy = pass.proxy && !pass.patch && !buffers.proxyIndices().empty();
  const bool onGpu = pass.gpuZ != nullptr;
  gl.glEnable(GL_DEPTH_TEST);
  gl.glDepthFunc(GL_LEQUAL);
  QOpenGLShaderProgram* program = onGpu ? gpu.program() : m_meshProgram.get();
  program->bind();
  program->setUniformValue("uModelView", pass.view);
  program->setUniformValue("uProjection", pass.projection);
  program->setUniformValue("uBaseColor", kMeshColor);
  program->setUniformValue("uLineColor", QVector4D(0, 0, 0, 0));
  if (onGpu) {
    gpu.setUniforms(gl, buffers.basisTexture(), *pass.gpuZ);
  } else {
    program->setUniformValue("uNormalMatrix", pass.view.normalMatrix());
  }
  QOpenGLVertexArrayObject::Binder vaoBinder(onGpu   ? &buffers.gpuVao()
                                             : proxy ? &buffers.proxyVao()
                                                     : &buffers.meshVao());
  const auto meshTriangles = static_cast<std::ptrdiff_t>(indices.size() / 3);
  const std::ptrdiff_t from = std::clamp<std::ptrdiff_t>(pass.firstTriangle, 0, meshTriangles);
  const std::ptrdiff_t to =
      pass.triangleCount < 0 ? meshTriangles : std::min<std::ptrdiff_t>(meshTriangles, from + pass.triangleCount);
  const auto count = static_cast<GLsizei>(pass.patch ? 3 * buffers.patchTriangles()
                                          : proxy    ? buffers.proxyIndices().size()
                                                     : 3 * (to - from));
  const std::size_t firstIndex =
      pass.patch ? 0 : (proxy ? (onGpu ? indices.size() : 0) : static_cast<std::size_t>(3 * from));
  if (pass.patch) buffers.bindPatch(gl);
  const auto* first = reinterpret_cast<const void*>(firstIndex * sizeof(std::uint32_t));
  // === fill pass, pushed back slightly so that the edges of the line pass win the depth test.
  if (pass.wireframe) {
    gl.glEnable(GL_POLYGON_OFFSET_FILL);
    gl.glPolygonOffset(1.0f, 1.0f);
  }
  if (count > 0) {
    gl.glDrawElements(GL_TRIANGLES, count, GL_UNSIGNED_INT, first);
  }
  gl.glDisable(GL_POLYGON_OFFSET_FILL);
  // === line pass: the same triangles as edges.
  if (pass.wireframe && count > 0) {
    program->setUniformValue("uLineColor", kWireColor);
    gl.glPolygonMode(GL_FRONT_AND_BACK, GL_LINE);
    gl.glDrawElements(GL_TRIANGLES, count, GL_UNSIGNED_INT, first);
    gl.glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
  }
  if (pass.patch) buffers.bindMeshTriangles();
  if (onGpu) {
    gpu.unbind(gl);
  }
  program->release();
  return count / 3;
}

void ScenePasses::beginReduced(QOpenGLFunctions_3_3_Core& gl, QSize reduced) {
  if (!m_sceneFbo || m_sceneFbo->size() != reduced) {
    m_sceneFbo = std::make_unique<QOpenGLFramebufferObject>(reduced, QOpenGLFramebufferObject::Depth);
  }
  m_sceneFbo->bind();
  gl.glViewport(0, 0, reduced.width(), reduced.height());
}

void ScenePasses::endReduced(QOpenGLFunctions_3_3_Core& gl, unsigned target, QSize reduced, QSize full) {
  gl.glBindFramebuffer(GL_DRAW_FRAMEBUFFER, target);
  gl.glBlitFramebuffer(0, 0, reduced.width(), reduced.height(), 0, 0, full.width(), full.height(), GL_COLOR_BUFFER_BIT,
                       GL_LINEAR);
  gl.glBindFramebuffer(GL_FRAMEBUFFER, target);
  gl.glViewport(0, 0, full.width(), full.height());
}

DepthImage ScenePasses::renderDepth(QOpenGLFunctions_3_3_Core& gl, QSize size, ViewportBuffers& buffers,
                                    GpuReconstructor& gpu, const MeshPass& pass) {
  if (!m_pickFbo || m_pickFbo->size() != size) {
    m_pickFbo = std::make_unique<QOpenGLFramebufferObject>(size, QOpenGLFramebufferObject::Depth);
  }
  m_pickFbo->bind();
  gl.glViewport(0, 0, size.width(), size.height());
  gl.glClearDepth(1.0);
  gl.glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  gl.glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
  drawMesh(gl, buffers, gpu, pass);
  gl.glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  DepthImage image;
  image.width = size.width();
  image.height = size.height();
  image.depth.resize(static_cast<std::size_t>(size.width()) * static_cast<std::size_t>(size.height()));
  gl.glPixelStorei(GL_PACK_ALIGNMENT, 4);
  gl.glReadPixels(0, 0, size.width(), size.height(), GL_DEPTH_COMPONENT, GL_FLOAT, image.depth.data());
  m_pickFbo->release();
  return image;
}

}  // namespace sc::app
