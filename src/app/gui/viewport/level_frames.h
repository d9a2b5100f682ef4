#pragma once
// LevelFrames: the frames of the level a MeshViewport shows, on the chosen reconstruction path. It holds the
// ShownLevel (the session's shared display level and the frame's Z), the two reconstructors and the path, and keeps
// ViewportBuffers' host positions and normals exactly as current as the next paint or gesture needs them: the CPU
// path reconstructs when a frame arrives (only the interactive proxy's vertices while the next paint may draw the
// proxy), the GPU path leaves them lagging until a gesture or a CPU frame of the full mesh asks. No GL calls: the GPU
// path's program lives here, its use is ScenePasses'.

#include "app/gui/mesh_viewport_types.h"
#include "app/gui/viewport/cpu_reconstructor.h"
#include "app/gui/viewport/gpu_reconstructor.h"
#include "app/gui/viewport/shown_level.h"
#include "app/gui/viewport/viewport_buffers.h"
#include "spectral/display_level.h"

#include <QVector3D>

#include <span>
#include <utility>

namespace sc::app {

class LevelFrames {
 public:
  /// `buffers`: the viewport's, outliving this object.
  LevelFrames(ViewportBuffers& buffers, ReconstructionPath path) : m_buffers(buffers), m_path(path) {}

  [[nodiscard]] const ShownLevel& shown() const { return m_shown; }
  [[nodiscard]] GpuReconstructor& gpu() { return m_gpu; }
  [[nodiscard]] ReconstructionPath path() const { return m_path; }

  /// Holds `level` (its K has one row per vertex of the buffers; buffers.rest() shows its rest positions relative to
  /// the viewport's origin, ViewportBuffers::shareLevel()) and marks the basis for upload. Nothing is shown until
  /// show(). Cost: O(m).
  void hold(spectral::SharedDisplayLevel level);
  /// Drops the level and the rest positions (a plain mesh, or none).
  void drop();
  /// A level's rest shape was shared into the buffers with its normals (ViewportBuffers::shareLevel()): it replaces
  /// the shown frame, like positionsGiven() but with nothing to compute. Cost: O(1).
  void restShared(FrameTimes& times);
  /// Shows X̂' + K·Z (see ShownLevel::show()); false, and nothing changes, for a Z of the wrong shape.
  bool show(const Eigen::MatrixXf& Z) { return m_shown.show(Z); }

  /// Explicit positions were written into the buffers: they replace the shown frame. Recomputes the normals of the
  /// mesh and of the proxy (their time is `times.normalsMs`; reconstructMs is 0). Cost: O(#V + #F).
  void positionsGiven(FrameTimes& times);
  /// Applies the shown frame on the path (its reconstruct and normals stages into `times`). `proxyOnly`: the next
  /// paint may draw the proxy, so the CPU path reconstructs only the proxy's vertices (when the proxy has its rows
  /// of K). Cost: CPU O(#V·m + #F) or O(#P·m + #T); GPU O(1).
  void apply(bool proxyOnly, FrameTimes& times);
  /// Before a frame of the full mesh from its own vertex buffer: the positions and normals that proxy-only frames
  /// or the GPU path left behind (their times are this frame's reconstruct and normals stages). Nothing on the GPU
  /// path.
  void ensureFullVertexData(FrameTimes& times);
  /// The host positions, current (reconstructed first when they lag). 3·#V floats relative to the origin.
  std::span<const float> currentPositions();
  /// The host positions as last reconstructed on the CPU, without reconstructing (on the GPU path they may lag the
  /// picture until something needs them current). 3·#V floats relative to the origin.
  [[nodiscard]] std::span<const float> lastPositions() const { return m_buffers.positions(); }
  /// The proxy's positions and normals for the current picture (after the proxy or the selection changed).
  void refreshProxy() { m_cpu.refreshProxy(m_shown, m_buffers); }
  /// The camera's scene bounds: exact from the host positions, or while they lag the shown frame from
  /// ShownLevel::bounds(), which needs no reconstruction.
  [[nodiscard]] std::pair<QVector3D, QVector3D> bounds() const;
  /// Whether the CPU path's host positions or normals lag the shown frame (ensureFullVertexData() would write them).
  [[nodiscard]] bool fullVertexDataLagging() const { return !gpuDrawing() && m_cpu.lagging(); }
  /// Whether bounds() is the conservative box of a lagging frame now (exact once the positions are current).
  [[nodiscard]] bool boundsConservative() const { return m_shown.showing() && m_cpu.positionsStale(); }

  /// Whether the GL objects exist (between the widget's initializeGL() and cleanup()).
  void setGlReady(bool ready) { m_glReady = ready; }
  [[nodiscard]] bool glReady() const { return m_glReady; }
  /// Whether the GPU path can draw the held basis (false until the GL objects exist).
  [[nodiscard]] bool gpuAvailable() const;
  /// Whether the next paint draws the shown frame on the GPU path.
  [[nodiscard]] bool gpuDrawing() const {
    return m_shown.showing() && m_path == ReconstructionPath::Gpu && gpuAvailable();
  }
  /// Chooses the path; Gpu falls back to Cpu where the existing context cannot draw the basis (call it again with
  /// path() once the GL objects exist). Returns whether the shown frame must be applied again (the path changed
  /// while showing).
  bool setPath(ReconstructionPath path);

 private:
  ViewportBuffers& m_buffers;
  ShownLevel m_shown;
  CpuReconstructor m_cpu;
  GpuReconstructor m_gpu;
  ReconstructionPath m_path;
  bool m_glReady = false;
};

}  // namespace sc::app
