#pragma once
// ScenePasses: the GL passes of MeshViewport's picture. The gradient background, the shaded mesh (with an optional
// wireframe pass over it) on either reconstruction path, the reduced-resolution offscreen target of adaptive
// frames, and the depth-only pass read back for picking. It owns the programs and framebuffers those need; the
// vertex data comes from ViewportBuffers, the GPU path's program and uniforms from GpuReconstructor.

#include "app/gui/mesh_viewport_types.h"
#include "app/gui/vertex_picking.h"
#include "spectral/display_level.h"

#include <Eigen/Core>

#include <QMatrix4x4>
#include <QOpenGLVertexArrayObject>
#include <QSize>

#include <memory>

class QOpenGLFramebufferObject;
class QOpenGLFunctions_3_3_Core;
class QOpenGLShaderProgram;

namespace sc::app {

class GpuReconstructor;
class StageClock;
class ViewportBuffers;

/// One mesh pass: the camera, what to draw and on which path.
struct MeshPass {
  QMatrix4x4 view;
  QMatrix4x4 projection;
  bool wireframe = false;                 ///< edges over the shaded triangles
  bool proxy = false;                     ///< the interactive proxy's triangles instead of the mesh's
  const Eigen::MatrixXf* gpuZ = nullptr;  ///< non-null: the GPU path draws X̂' + K·Z with this scaled Z (m by 3)
  int firstTriangle = 0;                  ///< the mesh's triangles from this one (not the proxy's: all of those)
  int triangleCount = -1;                 ///< how many of them (−1: to the last)
  bool patch = false;  ///< ViewportBuffers' patch triangles (uploadPatch()) instead of the mesh's or the proxy's
};

/// Where and how one picture is drawn.
struct FrameTarget {
  unsigned framebuffer = 0;  ///< the widget's framebuffer object
  QSize full;                ///< its size in device pixels
  double scale = 1.0;        ///< internal resolution: below 1 through the reduced target, stretched onto it
  bool finish = false;       ///< end with glFinish() (a measured frame: the rasteriser's time is part of it)
};

class ScenePasses {
 public:
  ScenePasses();
  ~ScenePasses();
  ScenePasses(const ScenePasses&) = delete;
  ScenePasses& operator=(const ScenePasses&) = delete;

  /// Compiles the programs and creates the background's vertex array (context current). Returns whether the mesh
  /// program exists (without it nothing but the background is drawn).
  bool create();
  /// Releases everything (context current); safe without create().
  void destroy();
  [[nodiscard]] bool created() const { return m_backgroundProgram != nullptr || m_meshProgram != nullptr; }
  [[nodiscard]] bool meshReady() const { return m_meshProgram != nullptr; }

  /// Clears colour and depth and draws the gradient into the bound framebuffer.
  void drawBackground(QOpenGLFunctions_3_3_Core& gl);
  /// Draws `pass` from `buffers` (uploaded). Returns the number of triangles drawn (0: no mesh).
  int drawMesh(QOpenGLFunctions_3_3_Core& gl, ViewportBuffers& buffers, GpuReconstructor& gpu, const MeshPass& pass);

  /// One picture into `target`: uploads the buffers (`K`: the GPU path's basis, or nullptr), draws the background,
  /// then `pass`. Fills the GL stages of `times` (upload, background, mesh with the stretch and finish) and its
  /// triangle count, each stage ended by `clock` (started here). Needs create().
  void drawFrame(QOpenGLFunctions_3_3_Core& gl, ViewportBuffers& buffers, GpuReconstructor& gpu,
                 const spectral::QuantizedBasis* K, const MeshPass& pass, const FrameTarget& target, StageClock& clock,
                 FrameTimes& times);

  /// Binds an offscreen target of `reduced` device pixels (re-created when the size changes) and its viewport.
  void beginReduced(QOpenGLFunctions_3_3_Core& gl, QSize reduced);
  /// Stretches it onto framebuffer `target` of `full` device pixels (linear filter) and binds that back.
  void endReduced(QOpenGLFunctions_3_3_Core& gl, unsigned target, QSize reduced, QSize full);

  /// The depth of `pass` at `size` device pixels, rendered into a single-sampled offscreen framebuffer and read
  /// back (the widget's own framebuffer may be multisampled and cannot be read as depth). Cost: one mesh pass and
  /// a read-back of 4 bytes per pixel.
  [[nodiscard]] DepthImage renderDepth(QOpenGLFunctions_3_3_Core& gl, QSize size, ViewportBuffers& buffers,
                                       GpuReconstructor& gpu, const MeshPass& pass);

 private:
  std::unique_ptr<QOpenGLShaderProgram> m_meshProgram;
  std::unique_ptr<QOpenGLShaderProgram> m_backgroundProgram;
  QOpenGLVertexArrayObject m_backgroundVao;
  std::unique_ptr<QOpenGLFramebufferObject> m_pickFbo;
  std::unique_ptr<QOpenGLFramebufferObject> m_sceneFbo;  // reduced-resolution frames
};

}  // namespace sc::app
