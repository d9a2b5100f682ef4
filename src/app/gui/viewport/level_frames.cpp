#include "app/gui/viewport/level_frames.h"

#include "app/gui/vertex_normals.h"
#include "app/gui/viewport/lap_timer.h"
#include "app/gui/viewport/vertex_arrays.h"

#include <QElapsedTimer>

namespace sc::app {

void LevelFrames::hold(spectral::SharedDisplayLevel level) {
  m_shown.hold(std::move(level));
  m_buffers.mark(ViewportBuffers::kBasis);
  setPath(m_path);  // nothing is shown yet: no frame to apply again
}

void LevelFrames::drop() {
  m_shown.clear();
  m_buffers.writeRest().clear();
  m_cpu.reset();
}

void LevelFrames::restShared(FrameTimes& times) {
  m_shown.stopShowing();
  m_cpu.reset();
  times.reconstructMs = times.normalsMs = 0.0;
  refreshProxy();
}

void LevelFrames::positionsGiven(FrameTimes& times) {
  m_shown.stopShowing();
  m_cpu.reset();
  times.reconstructMs = 0.0;
  QElapsedTimer timer;
  timer.start();
  std::vector<float>& normals = m_buffers.writeNormals();
  normals.resize(m_buffers.positions().size());
  vertexNormals(m_buffers.positions(), m_buffers.indices(), normals);
  refreshProxy();
  times.normalsMs = lapMs(timer);
}

void LevelFrames::apply(bool proxyOnly, FrameTimes& times) {
  if (m_path == ReconstructionPath::Cpu) {
    const HostStageTimes host = m_cpu.showFrame(m_shown, m_buffers, proxyOnly && m_buffers.proxy().hasBasis());
    times.reconstructMs = host.reconstructMs;
    times.normalsMs = host.normalsMs;
  } else {
    m_cpu.frameDrawnElsewhere();
    times.reconstructMs = times.normalsMs = 0.0;
  }
}

void LevelFrames::ensureFullVertexData(FrameTimes& times) {
  if (gpuDrawing() || !m_cpu.lagging()) {
    return;
  }
  const bool reconstructs = m_cpu.positionsStale();
  const HostStageTimes host = m_cpu.ensureVertexData(m_shown, m_buffers);
  if (reconstructs) {
    times.reconstructMs = host.reconstructMs;
  }
  times.normalsMs = host.normalsMs;
}

std::span<const float> LevelFrames::currentPositions() {
  m_cpu.ensurePositions(m_shown, m_buffers);
  return m_buffers.positions();
}

std::pair<QVector3D, QVector3D> LevelFrames::bounds() const {
  return boundsConservative() ? m_shown.bounds() : boundsOf(m_buffers.positions());
}

bool LevelFrames::gpuAvailable() const {
  const long long vertices = m_shown.empty() ? 0 : m_shown.K().rows();
  return m_glReady && m_buffers.basisTexture() != 0 && m_gpu.available(vertices, m_shown.basisSize());
}

bool LevelFrames::setPath(ReconstructionPath path) {
  if (path == ReconstructionPath::Gpu && m_glReady && !m_shown.empty() && !gpuAvailable()) {
    path = ReconstructionPath::Cpu;
  }
  const bool changed = path != m_path;
  m_path = path;
  return changed && m_shown.showing();
}

}  // namespace sc::app
