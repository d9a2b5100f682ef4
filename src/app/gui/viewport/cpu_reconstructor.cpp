#include "app/gui/viewport/cpu_reconstructor.h"

#include "app/gui/vertex_normals.h"
#include "app/gui/viewport/lap_timer.h"
#include "spectral/reconstruction_kernel.h"

namespace sc::app {

namespace {

void updateNormals(ViewportBuffers& buffers) {
  std::vector<float>& normals = buffers.writeNormals();
  normals.resize(buffers.positions().size());
  vertexNormals(buffers.positions(), buffers.indices(), normals);
}

}  // namespace

HostStageTimes CpuReconstructor::showFrame(const ShownLevel& shown, ViewportBuffers& buffers, bool proxyOnly) {
  HostStageTimes times;
  QElapsedTimer timer;
  timer.start();
  if (proxyOnly) {
    m_positionsStale = m_normalsStale = true;
    CompactProxy& proxy = buffers.writeProxyVertices();
    proxy.reconstruct(shown.Z());
    times.reconstructMs = lapMs(timer);
    proxy.updateNormals();
    times.normalsMs = lapMs(timer);
    return times;
  }
  m_positionsStale = true;
  times.reconstructMs = ensurePositions(shown, buffers);
  updateNormals(buffers);
  m_normalsStale = false;
  refreshProxy(shown, buffers);
  times.normalsMs = lapMs(timer);
  return times;
}

double CpuReconstructor::ensurePositions(const ShownLevel& shown, ViewportBuffers& buffers) {
  if (!m_positionsStale || shown.empty()) {
    return 0.0;
  }
  QElapsedTimer timer;
  timer.start();
  std::vector<float>& positions = buffers.writePositions();
  positions.resize(buffers.rest().size());
  spectral::reconstructInterleaved(shown.K(), buffers.rest(), shown.Z(), positions);
  m_positionsStale = false;
  m_normalsStale = true;  // recomputed by ensureVertexData() before a CPU frame of the mesh, if one comes
  return lapMs(timer);
}

HostStageTimes CpuReconstructor::ensureVertexData(const ShownLevel& shown, ViewportBuffers& buffers) {
  HostStageTimes times;
  if (!m_positionsStale && !m_normalsStale) {
    return times;
  }
  times.reconstructMs = ensurePositions(shown, buffers);
  QElapsedTimer timer;
  timer.start();
  updateNormals(buffers);
  m_normalsStale = false;
  times.normalsMs = lapMs(timer);
  return times;
}

void CpuReconstructor::refreshProxy(const ShownLevel& shown, ViewportBuffers& buffers) const {
  if (buffers.proxy().empty()) {
    return;
  }
  CompactProxy& proxy = buffers.writeProxyVertices();
  if (shown.showing() && m_positionsStale && proxy.hasBasis()) {
    proxy.reconstruct(shown.Z());
  } else {
    proxy.gatherPositions(buffers.positions());
  }
  proxy.updateNormals();
}

}  // namespace sc::app
