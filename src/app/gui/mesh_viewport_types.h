#pragma once
// Small value types of MeshViewport's interface: its tools, its reconstruction paths, its frame timings and the
// local user's view.

#include <QVector3D>

#include <optional>

namespace sc::app {

/// This user's view (MeshViewport::localView()), in the mesh's own coordinates: camera eye, target, up, and the
/// surface point under the mouse pointer (if any).
struct ViewportLocalView {
  QVector3D eye, target, up;
  std::optional<QVector3D> pointer;
  /// The centroid of the painted handle as last reconstructed on the CPU (LevelFrames::lastPositions()); none
  /// without a handle.
  std::optional<QVector3D> handle;
};

/// What a left drag does in the viewport. Right/middle drag always pans, the wheel always zooms and Alt+left drag
/// always orbits.
enum class ViewportTool {
  Orbit,        ///< left drag orbits the camera (the default).
  HandleBrush,  ///< left drag paints handle vertices, Shift+left drag erases them.
  AnchorBrush,  ///< left drag paints anchor vertices, Shift+left drag erases them.
  Drag,         ///< left drag on the mesh moves the handle (Ctrl: rotates it); off the mesh it orbits.
};

/// Where X' = X̂' + K·Z is evaluated for MeshViewport::showFrame(): on the CPU (spectral::reconstructInterleaved, then
/// CPU vertex normals and a position/normal upload) or in the vertex shader (K in a GL_RGBA32F texture buffer, Z in a
/// uniform array, rest positions as the vertex attribute; no per-vertex upload per frame). See MeshViewport.
enum class ReconstructionPath { Cpu, Gpu };

/// Wall-clock cost of the stages of the latest frame, in milliseconds (QElapsedTimer), for the status bar and
/// shapecast-bench-viewport. The host stages (reconstruct, normals, bounds) run in showFrame() / setPositions*();
/// the GL stages in paintGL(). The GL stages count the time to issue the commands (the rasteriser may still be
/// busy) unless a MeshViewport::setStageHook() observer waits for it (the benchmark's --profile: glFinish()).
struct FrameTimes {
  double reconstructMs = 0.0;  ///< X' = X̂' + K·Z on the CPU (0 on the GPU path and for explicit positions)
  double normalsMs = 0.0;      ///< CPU vertex normals (0 where the shader computes them)
  double boundsMs = 0.0;       ///< scene bounds for the camera
  double uploadMs = 0.0;       ///< buffer uploads in paintGL()
  double backgroundMs = 0.0;   ///< clear and gradient pass
  double meshMs = 0.0;         ///< the mesh pass(es)
  double overlayMs = 0.0;      ///< QPainter overlay (0 when nothing is shown over the view)
  double composeMs = 0.0;      ///< paint end → frameSwapped(): the swap of the viewport's window surface
  double renderScale = 1.0;    ///< internal resolution of the frame (see MeshViewport::setAdaptiveResolution)
  int triangles = 0;           ///< triangles drawn: the mesh's, or its interactive proxy's
  /// 0: the paint drew its picture; n > 0: it showed a progressive picture (MeshViewport::setProgressivePicture())
  /// of n slices drawn between paints, complete or so far, and meshMs is the time of its blit (and of its first slice)
  int pictureSlices = 0;
  [[nodiscard]] double hostMs() const { return reconstructMs + normalsMs + boundsMs; }
  [[nodiscard]] double paintMs() const { return uploadMs + backgroundMs + meshMs + overlayMs; }
  /// The whole frame: host stages, paintGL() and the composition/swap (the redraw part of the status bar's
  /// "reconstruction + redraw"; valid once frameSwapped() was emitted for the frame).
  [[nodiscard]] double totalMs() const { return hostMs() + paintMs() + composeMs; }
};

}  // namespace sc::app
