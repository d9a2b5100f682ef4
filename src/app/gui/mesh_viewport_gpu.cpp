// MeshViewport, the reconstruction side: the basis and coefficients, the CPU and GPU paths (X' = X̂' + K·Z in the
// vertex shader from a texture buffer), the transform-feedback read-back and the path timing.

#include "app/gui/mesh_shaders.h"
#include "app/gui/mesh_viewport.h"
#include "app/gui/vertex_normals.h"
#include "spectral/reconstruction_kernel.h"

#include <QCoreApplication>
#include <QElapsedTimer>
#include <QOpenGLContext>
#include <QOpenGLFunctions_3_3_Core>
#include <QOpenGLShaderProgram>
#include <QThread>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>
#include <utility>

namespace sc::app {

namespace {

constexpr int kBasisTextureUnit = 0;
constexpr unsigned long kFrameGapMs = 20;  // > one 60 Hz display frame

int groupsOf(int columns) { return (columns + 3) / 4; }

double median(std::vector<double> values) {
  if (values.empty()) {
    return std::numeric_limits<double>::infinity();
  }
  std::sort(values.begin(), values.end());
  const std::size_t mid = values.size() / 2;
  return values.size() % 2 == 1 ? values[mid] : 0.5 * (values[mid - 1] + values[mid]);
}

}  // namespace

void MeshViewport::dropBasis() {
  m_displayLevel.reset();
  m_basis.resize(0, 0);
  m_rest.clear();
  m_coefficients.resize(0, 0);
  m_basisColumns = 0;
  m_basisMaxRowNorm = 0.0f;
  m_proxy.clearBasis();
  m_showingCoefficients = false;
  m_hostPositionsStale = false;
  m_basisDirty = false;
  m_restDirty = false;
  m_timings.reset();
}

void MeshViewport::setReconstructionBasis(const spectral::RowMatrixXf& K, std::span<const float> rest) {
  const auto n = static_cast<std::size_t>(m_vertexCount);
  assert(static_cast<std::size_t>(K.rows()) == n && rest.size() == 3 * n && K.cols() > 0 &&
         "setReconstructionBasis needs #V rows of K and 3·#V rest floats of the current mesh");
  if (static_cast<std::size_t>(K.rows()) != n || rest.size() != 3 * n || K.cols() == 0 || n == 0) {
    return;
  }
  dropBasis();
  const auto m = static_cast<int>(K.cols());
  const int padded = 4 * groupsOf(m);
  m_basis = spectral::RowMatrixXf::Zero(K.rows(), padded);
  m_basis.leftCols(m) = K;
  m_basisColumns = m;
  m_basisMaxRowNorm = K.rowwise().norm().maxCoeff();
  const float origin[3] = {static_cast<float>(m_origin(0)), static_cast<float>(m_origin(1)),
                           static_cast<float>(m_origin(2))};
  m_rest.resize(3 * n);
  for (std::size_t i = 0; i < 3 * n; ++i) {
    m_rest[i] = rest[i] - origin[i % 3];
  }
  Eigen::Map<const Eigen::Matrix<float, Eigen::Dynamic, 3, Eigen::RowMajor>> R(m_rest.data(), m_vertexCount, 3);
  m_restLo = R.colwise().minCoeff().transpose();
  m_restHi = R.colwise().maxCoeff().transpose();
  m_coefficients = Eigen::MatrixXf::Zero(padded, 3);
  if (!m_proxy.empty()) {
    m_proxy.setBasis(m_basis, m_rest);
  }
  m_basisDirty = true;
  m_restDirty = true;
  if (m_path == ReconstructionPath::Gpu && m_glReady && !gpuReconstructionAvailable()) {
    m_path = ReconstructionPath::Cpu;
  }
}

void MeshViewport::setDisplayLevel(spectral::SharedDisplayLevel level) {
  if (!level) {
    clearMesh();
    return;
  }
  setMesh(level->level.restV, level->level.F);
  setReconstructionBasis(level->level.K, level->rest);
  m_displayLevel = std::move(level);
}

void MeshViewport::showFrame(const spectral::DisplayFrame& frame) {
  if (!m_displayLevel) return;
  if (frame.Z.size() == 0) {
    setCoefficients(Eigen::MatrixXf::Zero(m_displayLevel->basisSize(), 3));
  } else {
    setCoefficients(frame.Z);
  }
}

void MeshViewport::setCoefficients(const Eigen::MatrixXf& Z) {
  assert(Z.rows() == m_basisColumns && Z.cols() == 3 && "setCoefficients needs an m by 3 Z for the current basis");
  if (m_basisColumns == 0 || Z.rows() != m_basisColumns || Z.cols() != 3) {
    return;
  }
  m_coefficients.topRows(m_basisColumns) = Z;
  m_showingCoefficients = true;
  applyCoefficients();
}

// Shows rest + K·Z on the current path: the CPU path reconstructs (and computes normals) now, only the proxy's
// vertices while the next frame may draw the proxy (the mesh's follow in ensureFullVertexData()); the GPU path only
// widens the camera bounds and repaints.
void MeshViewport::applyCoefficients() {
  QElapsedTimer timer;
  timer.start();
  if (m_path == ReconstructionPath::Cpu && m_proxy.hasBasis() && proxyMayDraw()) {
    m_hostPositionsStale = true;
    m_normalsStale = true;
    m_proxy.reconstruct(m_coefficients);
    m_frameTimes.reconstructMs = lapMs(timer);
    m_proxy.updateNormals();
    m_proxyDataDirty = true;
    m_frameTimes.normalsMs = lapMs(timer);
    updateBounds();
    m_frameTimes.boundsMs = lapMs(timer);
    markMoved();
    return;
  }
  if (m_path == ReconstructionPath::Cpu) {
    m_positions.resize(m_rest.size());
    spectral::reconstructInterleaved(m_basis, m_rest, m_coefficients, m_positions);
    m_hostPositionsStale = false;
    m_frameTimes.reconstructMs = lapMs(timer);
    positionsChanged();
    return;
  }
  m_hostPositionsStale = true;
  updateBounds();
  m_frameTimes.reconstructMs = 0.0;
  m_frameTimes.normalsMs = 0.0;
  m_frameTimes.boundsMs = lapMs(timer);
  markMoved();
}

void MeshViewport::ensureHostPositions() {
  if (!m_hostPositionsStale) {
    return;
  }
  m_positions.resize(m_rest.size());
  spectral::reconstructInterleaved(m_basis, m_rest, m_coefficients, m_positions);
  m_hostPositionsStale = false;
  // The normals are not needed on the GPU path (the CPU path recomputes them: applyCoefficients() when it takes
  // over, ensureFullVertexData() before a frame of the mesh).
  m_normalsStale = true;
}

// Before drawing the full mesh from the mesh VAO: the positions and normals that proxy-only frames left behind,
// reconstructed and marked for upload (their times are this frame's reconstruct and normals stages).
void MeshViewport::ensureFullVertexData() {
  if (gpuDrawing() || (!m_hostPositionsStale && !m_normalsStale)) {
    return;
  }
  QElapsedTimer timer;
  timer.start();
  if (m_hostPositionsStale) {
    ensureHostPositions();
    m_frameTimes.reconstructMs = lapMs(timer);
  }
  m_normals.resize(m_positions.size());
  vertexNormals(m_positions, m_indices, m_normals);
  m_normalsStale = false;
  m_frameTimes.normalsMs = lapMs(timer);
  m_vertexDataDirty = true;
}

std::vector<float> MeshViewport::hostPositions() {
  ensureHostPositions();
  std::vector<float> xyz(m_positions.size());
  for (std::size_t i = 0; i < xyz.size(); ++i) {
    xyz[i] = m_positions[i] + static_cast<float>(m_origin(static_cast<Eigen::Index>(i % 3)));
  }
  return xyz;
}

void MeshViewport::setReconstructionPath(ReconstructionPath path) {
  if (path == ReconstructionPath::Gpu && m_glReady && hasReconstructionBasis() && !gpuReconstructionAvailable()) {
    path = ReconstructionPath::Cpu;
  }
  const bool changed = path != m_path;
  m_path = path;
  if (changed && m_showingCoefficients) {
    applyCoefficients();
  }
}

bool MeshViewport::gpuReconstructionAvailable() const {
  if (!m_glReady || !m_reconstructProgram || m_basisBuffer == 0) {
    return false;
  }
  if (m_basisColumns == 0) {
    return true;
  }
  const int groups = groupsOf(m_basisColumns);
  return groups <= shaders::kMaxGroups && static_cast<long long>(m_vertexCount) * groups <= m_maxTextureBufferTexels;
}

bool MeshViewport::gpuDrawing() const {
  return m_showingCoefficients && m_path == ReconstructionPath::Gpu && gpuReconstructionAvailable();
}

void MeshViewport::createGpuObjects() {
  if (m_gl33 == nullptr) {
    return;
  }
  m_reconstructProgram =
      shaders::makeProgram(shaders::kMeshReconstructVertex, shaders::kMeshFragment, [this](GLuint program) {
        const char* varyings[] = {"vModelPosition"};
        m_gl33->glTransformFeedbackVaryings(program, 1, varyings, GL_INTERLEAVED_ATTRIBS);
      });
  if (!m_reconstructProgram) {
    return;
  }
  GLint maxTexels = 0;
  glGetIntegerv(GL_MAX_TEXTURE_BUFFER_SIZE, &maxTexels);
  m_maxTextureBufferTexels = maxTexels;
  glGenBuffers(1, &m_basisBuffer);
  glGenTextures(1, &m_basisTexture);
  glBindBuffer(GL_TEXTURE_BUFFER, m_basisBuffer);
  glBindTexture(GL_TEXTURE_BUFFER, m_basisTexture);
  m_gl33->glTexBuffer(GL_TEXTURE_BUFFER, GL_RGBA32F, m_basisBuffer);
  glBindTexture(GL_TEXTURE_BUFFER, 0);
  glBindBuffer(GL_TEXTURE_BUFFER, 0);

  // The VAO: rest positions at location 0, the shared tint buffer at 2 and the shared index buffer.
  m_gpuVao.create();
  QOpenGLVertexArrayObject::Binder vaoBinder(&m_gpuVao);
  m_restBuffer.create();
  m_restBuffer.setUsagePattern(QOpenGLBuffer::StaticDraw);
  m_restBuffer.bind();
  glEnableVertexAttribArray(0);
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 0, nullptr);
  m_restBuffer.release();
  m_tintBuffer.bind();
  glEnableVertexAttribArray(2);
  glVertexAttribPointer(2, 4, GL_UNSIGNED_BYTE, GL_TRUE, 0, nullptr);
  m_tintBuffer.release();
  m_indexBuffer.bind();  // VAO state
  m_restDirty = true;
  m_basisDirty = true;
}

void MeshViewport::destroyGpuObjects() {
  m_reconstructProgram.reset();
  m_gpuVao.destroy();
  m_restBuffer.destroy();
  if (m_basisTexture != 0) {
    glDeleteTextures(1, &m_basisTexture);
  }
  for (GLuint* buffer : {&m_basisBuffer, &m_feedbackBuffer}) {
    if (*buffer != 0) {
      glDeleteBuffers(1, buffer);
    }
  }
  m_basisTexture = m_basisBuffer = m_feedbackBuffer = 0;
  m_maxTextureBufferTexels = 0;
}

// Binds K to its texture unit and sets Z (the reconstruct program is bound).
void MeshViewport::setGpuUniforms() {
  const int groups = groupsOf(m_basisColumns);
  glActiveTexture(GL_TEXTURE0 + kBasisTextureUnit);
  glBindTexture(GL_TEXTURE_BUFFER, m_basisTexture);
  m_reconstructProgram->setUniformValue("uBasis", kBasisTextureUnit);
  m_reconstructProgram->setUniformValue("uGroups", groups);
  m_reconstructProgram->setUniformValue("uFaceNormals", true);
  // Z is column-major 4G by 3: x column then y then z, each G vec4, exactly uZ's layout.
  glUniform4fv(m_reconstructProgram->uniformLocation("uZ"), 3 * groups, m_coefficients.data());
}

std::vector<float> MeshViewport::gpuReconstructedPositions() {
  std::vector<float> xyz;
  if (!m_glReady || m_basisColumns == 0 || !gpuReconstructionAvailable() || context() == nullptr) {
    return xyz;
  }
  makeCurrent();
  uploadIfDirty();
  const auto bytes = static_cast<GLsizeiptr>(m_rest.size() * sizeof(float));
  if (m_feedbackBuffer == 0) {
    glGenBuffers(1, &m_feedbackBuffer);
  }
  m_gl33->glBindBuffer(GL_TRANSFORM_FEEDBACK_BUFFER, m_feedbackBuffer);
  m_gl33->glBufferData(GL_TRANSFORM_FEEDBACK_BUFFER, bytes, nullptr, GL_STREAM_READ);
  m_reconstructProgram->bind();
  m_reconstructProgram->setUniformValue("uModelView", QMatrix4x4());
  m_reconstructProgram->setUniformValue("uProjection", QMatrix4x4());
  setGpuUniforms();
  {
    QOpenGLVertexArrayObject::Binder vaoBinder(&m_gpuVao);
    glEnable(GL_RASTERIZER_DISCARD);
    m_gl33->glBindBufferBase(GL_TRANSFORM_FEEDBACK_BUFFER, 0, m_feedbackBuffer);
    m_gl33->glBeginTransformFeedback(GL_POINTS);
    glDrawArrays(GL_POINTS, 0, m_vertexCount);  // gl_VertexID = i, as in the indexed draw
    m_gl33->glEndTransformFeedback();
    glDisable(GL_RASTERIZER_DISCARD);
  }
  xyz.resize(m_rest.size());
  m_gl33->glGetBufferSubData(GL_TRANSFORM_FEEDBACK_BUFFER, 0, bytes, xyz.data());
  m_gl33->glBindBufferBase(GL_TRANSFORM_FEEDBACK_BUFFER, 0, 0);
  m_gl33->glBindBuffer(GL_TRANSFORM_FEEDBACK_BUFFER, 0);
  glBindTexture(GL_TEXTURE_BUFFER, 0);
  m_reconstructProgram->release();
  doneCurrent();
  for (std::size_t i = 0; i < xyz.size(); ++i) {
    xyz[i] += static_cast<float>(m_origin(static_cast<Eigen::Index>(i % 3)));
  }
  return xyz;
}

ReconstructionTimings MeshViewport::measureReconstructionPaths(int frames) {
  ReconstructionTimings timings{std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity()};
  if (m_basisColumns == 0 || !isVisible() || context() == nullptr || !m_glReady) {
    return timings;
  }
  const ReconstructionPath savedPath = m_path;
  const bool savedShowing = m_showingCoefficients;
  const Eigen::MatrixXf savedZ = m_coefficients.topRows(m_basisColumns);
  for (const ReconstructionPath path : {ReconstructionPath::Cpu, ReconstructionPath::Gpu}) {
    setReconstructionPath(path);
    if (m_path != path) {
      continue;  // unavailable here: stays +∞
    }
    std::vector<double> ms;
    for (int frame = 0; frame < std::max(1, frames); ++frame) {
      const Eigen::MatrixXf Z = savedZ * (1.0f + 0.001f * static_cast<float>(frame % 2));
      // Qt 6 defers a repaint() that follows the previous composition within one display frame: let pending
      // updates run, then wait out the frame so that the repaint below is synchronous.
      QCoreApplication::processEvents();
      QThread::msleep(kFrameGapMs);
      const int painted = m_paintCount;
      QElapsedTimer timer;
      timer.start();
      setCoefficients(Z);
      repaint();
      makeCurrent();
      glFinish();
      doneCurrent();
      if (m_paintCount != painted) {
        ms.push_back(static_cast<double>(timer.nsecsElapsed()) * 1e-6);
      }
    }
    (path == ReconstructionPath::Cpu ? timings.cpuMs : timings.gpuMs) = median(std::move(ms));
  }
  setReconstructionPath(savedPath);
  m_coefficients.topRows(m_basisColumns) = savedZ;
  m_showingCoefficients = savedShowing;
  if (savedShowing) {
    applyCoefficients();
  }
  m_timings = timings;
  return timings;
}

ReconstructionPath MeshViewport::fasterPath() {
  if (!m_timings) {
    const ReconstructionTimings timings = measureReconstructionPaths();
    if (!std::isfinite(timings.cpuMs) && !std::isfinite(timings.gpuMs)) {
      return ReconstructionPath::Cpu;  // nothing measured (not shown, no basis): do not cache
    }
  }
  return m_timings->faster();
}

}  // namespace sc::app
