#pragma once
// CpuReconstructor: the CPU path of a shown level's frames. X̂' + K·Z comes from the spectral kernel
// (spectral::reconstructInterleaved: on the shared K in place for the mesh, on the proxy's gathered rows of K for the
// interactive proxy's vertices, CompactProxy::reconstruct()); normals from vertexNormals(). It also keeps track of what
// the host buffers lag behind the shown frame, so that the mesh's positions are reconstructed only when someone needs
// them.

#include "app/gui/viewport/shown_level.h"
#include "app/gui/viewport/viewport_buffers.h"

namespace sc::app {

/// Milliseconds spent in the host stages of one frame (see FrameTimes).
struct HostStageTimes {
  double reconstructMs = 0.0;
  double normalsMs = 0.0;
};

class CpuReconstructor {
 public:
  /// A new frame of `shown` (showing()) on the CPU path. `proxyOnly` (needs the proxy's basis,
  /// CompactProxy::setBasis()): only the proxy's vertices now (positions and normals, O(#P·m + #T)); the mesh's
  /// positions and normals lag until ensureVertexData(). Otherwise the mesh's (O(#V·m + #F)) and the proxy's gathered
  /// from them. Marks what it wrote in `buffers`.
  HostStageTimes showFrame(const ShownLevel& shown, ViewportBuffers& buffers, bool proxyOnly);
  /// A frame drawn elsewhere (the GPU path): the host positions and normals lag the shown frame.
  void frameDrawnElsewhere() { m_positionsStale = m_normalsStale = true; }
  /// The host positions were given explicitly (or reset): nothing lags.
  void reset() { m_positionsStale = m_normalsStale = false; }
  /// Whether buffers.positions() lag the shown frame.
  [[nodiscard]] bool positionsStale() const { return m_positionsStale; }
  /// Whether buffers.positions() or buffers.normals() lag the shown frame.
  [[nodiscard]] bool lagging() const { return m_positionsStale || m_normalsStale; }

  /// Makes buffers.positions() current (reconstructs when they lag; the normals then lag). Returns its time, ms.
  double ensurePositions(const ShownLevel& shown, ViewportBuffers& buffers);
  /// Positions and normals current, for a frame of the full mesh on the CPU path.
  HostStageTimes ensureVertexData(const ShownLevel& shown, ViewportBuffers& buffers);
  /// The proxy's positions for the current picture: reconstructed from its rows of K (when it has them) while the
  /// mesh's positions lag a shown frame, else gathered from them; then its normals. Cost: O(#P·m + #T) or O(#P + #T).
  void refreshProxy(const ShownLevel& shown, ViewportBuffers& buffers) const;

 private:
  bool m_positionsStale = false;  // buffers.positions() lag X̂' + K·Z
  bool m_normalsStale = false;    // buffers.normals() lag buffers.positions() or the shown frame
};

}  // namespace sc::app
