#pragma once
// RendererDefaults: what a new MeshViewport chooses from the OpenGL renderer of this machine and the environment
// (multisampling, reconstruction path, adaptive resolution, progressive pictures). Each is probed once per process with
// an offscreen context created from the default surface format (needs a QGuiApplication).

#include "app/gui/mesh_viewport_types.h"

#include <QString>
#include <QSurfaceFormat>

namespace sc::app {

struct RendererDefaults {
  /// OpenGL 3.3 core, 24-bit depth, no multisampling (each viewport asks for its own samples).
  static QSurfaceFormat preferredSurfaceFormat();
  /// Empty when the display platform can show OpenGL widgets (not "offscreen", "minimal", "vnc" or "linuxfb") and an
  /// OpenGL 3.3 core context can be created from the default format; otherwise what is missing, in a sentence for
  /// the user.
  static QString openGlProblem();
  /// The GL_RENDERER string of a probe context created from the default format (empty when none can be made).
  static QString rendererName();
  /// Whether rendererName() names a software rasteriser (llvmpipe, softpipe or "software").
  static bool softwareRenderer();
  /// $SHAPECAST_MSAA when set (an integer ≥ 0), otherwise 0 on a software rasteriser and 4 otherwise.
  static int sampleCount();
  /// $SHAPECAST_RECONSTRUCTION ("cpu" or "gpu") when set, otherwise Cpu on a software rasteriser, Gpu otherwise.
  static ReconstructionPath reconstructionPath();
  /// $SHAPECAST_ADAPTIVE_RESOLUTION (0/1) when set, otherwise on for a software rasteriser only.
  static bool adaptiveResolution();
  /// $SHAPECAST_PROGRESSIVE_TRIANGLES (an integer ≥ 0; 0: never) when set, otherwise
  /// ProgressivePicture::kDefaultMinimumTriangles: the meshes whose full picture is drawn in slices.
  static int progressiveMinimumTriangles();
};

}  // namespace sc::app
