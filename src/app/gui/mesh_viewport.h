#pragma once
// MeshViewport: an OpenGL 3.3 core view of one triangle mesh, with orbit/pan/zoom, a selection brush and a handle
// drag. View only: the camera math lives in OrbitCamera, the normals in vertexNormals(), picking in
// vertex_picking.h and the drag pose in DragGesture; this class owns the GL objects and the host-side buffers and
// turns mouse gestures into intent signals (handlePainted, dragMoved, …) that a controller maps to session calls.

#include "app/gui/compact_proxy.h"
#include "app/gui/mesh_viewport_resolution.h"
#include "app/gui/mesh_viewport_types.h"
#include "app/gui/orbit_camera.h"
#include "app/gui/vertex_picking.h"
#include "spectral/display_level.h"
#include "spectral/resolution_level.h"

#include <Eigen/Core>

#include <QElapsedTimer>
#include <QOpenGLBuffer>
#include <QOpenGLFunctions>
#include <QOpenGLVertexArrayObject>
#include <QOpenGLWidget>
#include <QPoint>
#include <QString>
#include <QSurfaceFormat>
#include <QTimer>

#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <vector>

class QOpenGLFramebufferObject;
class QOpenGLFunctions_3_3_Core;
class QOpenGLShaderProgram;

namespace sc::app {

class DragGesture;

/// Renders a triangle mesh with area-weighted vertex normals, two-light Blinn–Phong shading over a vertical
/// gradient background, framed on its vertices; optionally with its edges drawn over it (wireframe) and with the
/// handle (orange-red) and anchor (blue) vertices tinted.
///
/// Mouse: see ViewportTool; a double click re-frames. Brush picking is a real visibility test: at the start of
/// each stroke the mesh is rendered into an offscreen depth buffer that is read back, and only vertices within
/// brushRadius() pixels of the cursor whose depth matches the rendered surface are painted (projectToScreen()).
///
/// GL lifetime follows Qt's hellogl2: nothing GL happens in the constructor; GL objects are made in
/// initializeGL() and released in cleanup(), which runs on QOpenGLContext::aboutToBeDestroyed and in the
/// destructor. Setters only update host-side data, mark it dirty and call update(); paintGL() uploads lazily.
///
/// Multisampling: the widget asks for defaultSampleCount() samples (4 on a real GPU, none on a software
/// rasteriser such as Mesa llvmpipe, where 4× multisampling alone costs tens of ms per frame; the environment
/// variable SHAPECAST_MSAA overrides it), or what setSampleCount() sets before the widget is first shown.
///
/// Deformation frames come either as positions (setPositions(), setPositionsInterleaved()) or, after
/// setReconstructionBasis(), as coefficients Z (setCoefficients()), reconstructed on the path chosen by
/// setReconstructionPath(). On the GPU path the shading uses face normals (screen-space derivatives of the
/// reconstructed position in the fragment shader): exact for the drawn triangles, so no per-frame read-back or CPU
/// work at all, at the price of a faceted look that smooth CPU vertex normals do not have (invisible at 100k
/// vertices, visible on a coarse level). Host positions for picking and dragging are reconstructed on the CPU
/// lazily, only when a gesture starts.
///
/// Adaptive resolution (setAdaptiveResolution(), on by default on software rasterisers): frames that follow each
/// other quickly are drawn at a reduced internal resolution chosen from the measured paint time, and the view
/// redraws itself at full resolution once idle. frameTimes() reports each frame's stages.
///
/// Signals carry std::vector / Eigen values and are meant for direct (same-thread) connections.
class MeshViewport : public QOpenGLWidget, protected QOpenGLFunctions {
  Q_OBJECT
  Q_DISABLE_COPY_MOVE(MeshViewport)

 public:
  static constexpr double kDefaultBrushRadius = 30.0;  ///< pixels.
  static constexpr int kHintMilliseconds = 2000;       ///< how long a drag hint stays on screen.

  /// Largest m the GPU reconstruction path handles (Z lives in a uniform array of 3·⌈m/4⌉ vec4).
  static constexpr int kMaxGpuBasisSize = 256;

  /// The format this widget needs (OpenGL 3.3 core, 24-bit depth; no multisampling: each MeshViewport asks for
  /// its own samples, see defaultSampleCount()). Pass it to QSurfaceFormat::setDefaultFormat() before
  /// constructing the QApplication.
  static QSurfaceFormat preferredSurfaceFormat();

  /// Samples a new MeshViewport asks for: $SHAPECAST_MSAA when set (an integer ≥ 0), otherwise 0 when the
  /// OpenGL renderer is a software rasteriser (GL_RENDERER names llvmpipe, softpipe or software) and 4 otherwise.
  /// Probed once per process with an offscreen context (needs a QGuiApplication).
  static int defaultSampleCount();
  /// The GL_RENDERER string of a probe context created from the default format (empty when none can be made).
  static QString rendererName();

  /// Multisample count of this widget's framebuffer; takes effect only before the widget is first shown.
  void setSampleCount(int samples);
  [[nodiscard]] int sampleCount() const { return format().samples(); }

  explicit MeshViewport(QWidget* parent = nullptr);
  ~MeshViewport() override;

  /// Replaces the mesh, computes vertex normals and frames the camera on it (resetView()). Clears the selection
  /// (without emitting handlePainted/anchorsPainted) and ends any gesture.
  /// @param[in] V  #V by 3 positions (finite).
  /// @param[in] F  #F by 3 indices into V.
  /// Emits meshChanged(). An empty V or F shows the background only.
  void setMesh(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F);

  /// Moves the vertices of the current mesh (e.g. one deformation frame) and recomputes the normals.
  /// @param[in] V  #V by 3 positions, same #V as the mesh given to setMesh().
  /// Does not re-frame the camera and does not emit meshChanged(). A V with another row count is a programming
  /// error: asserted in debug builds, ignored in release builds.
  void setPositions(const Eigen::MatrixXd& V);

  /// The per-frame fast path of setPositions(): the same contract, from flat floats, with no Eigen conversion.
  /// @param[in] xyz  3·#V floats, x y z per vertex, in the coordinates given to setMesh().
  /// Recomputes the normals in float (O(#V + #F)); the upload happens in the next paintGL().
  void setPositionsInterleaved(std::span<const float> xyz);

  /// Removes the mesh (background only). Emits meshChanged().
  void clearMesh();

  /// A coarse triangulation of the current mesh's own vertices (model::proxyTriangles()) that frames draw instead
  /// of the mesh's triangles while the shape or the camera moves, with adaptive resolution on. On a software
  /// rasteriser a dense mesh's frame costs per triangle at any pixel scale (vertex and setup work, and a fragment
  /// block per tiny triangle), so a moving dense mesh is drawn as its proxy, and in full once idle
  /// (kIdleRestoreMs). A frame uses the proxy only when it is interactive (see setAdaptiveResolution()), the
  /// positions or the camera changed since the previous frame, no wireframe is shown, no brush stroke is in
  /// progress, and the proxy keeps at least one vertex of each non-empty selection group (handles, anchors; so that
  /// a small selection never vanishes). The proxy has its own compact vertex buffer (CompactProxy) and is shaded with
  /// normals over its own triangles. It follows every deformation: explicit positions are gathered from the mesh's;
  /// on the CPU path, while proxy frames are possible, setCoefficients() reconstructs only the proxy's vertices
  /// (a tenth of the work for the 100k dragon) and the mesh's positions and normals follow lazily, when a frame of the
  /// full mesh, picking or a caller (hostPositions()) needs them. Picking and idle frames use the full mesh.
  /// @param[in] triangles  #P by 3 indices into the current mesh's vertices; empty removes the proxy.
  /// setMesh() and clearMesh() remove it. An index out of range is a programming error (asserted; in release builds
  /// the call is ignored and the previous proxy stays).
  void setInteractiveProxy(const Eigen::MatrixXi& triangles);
  /// Triangles of the interactive proxy (0: none).
  [[nodiscard]] int proxyTriangleCount() const { return static_cast<int>(m_proxyIndices.size() / 3); }

  /// The one-way frame path (docs/architecture.md): shows `level` (its rest mesh, faces and K; held by pointer, the
  /// viewport's reconstruction reads the shared K) and frames the camera on it, like setMesh(). nullptr: clearMesh().
  void setDisplayLevel(spectral::SharedDisplayLevel level);
  /// Shows one frame of the displayed level: X̂' + K·frame.Z (the rest shape for an empty Z), like setCoefficients().
  void showFrame(const spectral::DisplayFrame& frame);
  [[nodiscard]] const spectral::SharedDisplayLevel& displayLevel() const { return m_displayLevel; }

  /// Sets the reduced basis of the current mesh for setCoefficients(): X' = rest + K·Z.
  /// @param[in] K  #V by m basis (float32, row-major), e.g. spectral::ResolutionLevel::K; #V of the current mesh.
  /// @param[in] rest  3·#V floats, the rest positions x y z per vertex, in the coordinates given to setMesh().
  /// Copies both (K padded to a multiple of 4 columns); setMesh() and clearMesh() drop them. Does not change the
  /// picture until setCoefficients(). Mismatched sizes are a programming error (asserted; ignored in release).
  void setReconstructionBasis(const spectral::RowMatrixXf& K, std::span<const float> rest);
  [[nodiscard]] bool hasReconstructionBasis() const { return m_basisColumns > 0; }

  /// Shows the frame rest + K·Z on the current path (the per-frame call of a client).
  /// @param[in] Z  m by 3 coefficients (m = K's columns). Needs setReconstructionBasis(); ignored otherwise.
  /// CPU path: reconstructs, recomputes normals and bounds now (O(#V·m + #F)), uploads in paintGL(); while a frame
  /// may draw the interactive proxy, only the proxy's vertices (O(#P·m + #T)), the mesh's following when needed
  /// (see setInteractiveProxy()). GPU path: O(m) here; paintGL() uploads 12·m bytes of uniforms and the vertex
  /// shader does the rest.
  void setCoefficients(const Eigen::MatrixXf& Z);

  /// The path a new viewport starts with: $SHAPECAST_RECONSTRUCTION ("cpu" or "gpu") when set, otherwise Cpu on a
  /// software rasteriser (where shapecast-bench-viewport measures the CPU path faster: llvmpipe shades vertices on
  /// one thread, and 100k vertices × m/4 texel fetches cost more than the CPU kernel and normals) and Gpu on a real
  /// GPU. Probed once per process (see defaultSampleCount()).
  static ReconstructionPath defaultReconstructionPath();
  /// Chooses where setCoefficients() frames are reconstructed (default defaultReconstructionPath()). Gpu falls back to
  /// Cpu where the context cannot do it (shader failed, m > kMaxGpuBasisSize, K larger than
  /// GL_MAX_TEXTURE_BUFFER_SIZE).
  void setReconstructionPath(ReconstructionPath path);
  [[nodiscard]] ReconstructionPath reconstructionPath() const { return m_path; }
  /// Whether the GPU path can draw the current basis (false until the GL context exists).
  [[nodiscard]] bool gpuReconstructionAvailable() const;

  /// Times both paths on this widget (must be shown, with a basis): `frames` frames each of setCoefficients()
  /// with a slightly varied Z, a synchronous repaint() and glFinish(); returns the medians and caches them.
  /// Restores the path and Z (shown again if they were). An unavailable path is +∞. Cost: 2·frames repaints.
  ReconstructionTimings measureReconstructionPaths(int frames = 10);
  /// The faster path here: the cached measureReconstructionPaths() result, measured now (10 frames each) if
  /// there is none since the last setReconstructionBasis(). Cpu when nothing can be measured.
  ReconstructionPath fasterPath();
  [[nodiscard]] const std::optional<ReconstructionTimings>& reconstructionTimings() const { return m_timings; }

  /// Stage times of the latest frame (see FrameTimes); the host stages are those of the latest position change.
  [[nodiscard]] const FrameTimes& frameTimes() const { return m_frameTimes; }
  /// Profiling: when on, paintGL() calls glFinish() after each GL stage so that FrameTimes attributes the
  /// rasteriser's work to the stage that caused it (slower overall: no overlap of CPU and GPU). Default off.
  void setProfiling(bool on) { m_profiling = on; }

  /// Paint time (upload, background and mesh passes, resolve) that adaptive resolution keeps frames within, ms.
  static constexpr double kPaintBudgetMs = 18.0;
  /// A paint less than this long after the previous one is interactive; one this long after it, or the repaint
  /// that follows this long without paints, is drawn at full resolution.
  static constexpr int kIdleRestoreMs = 300;
  /// Adaptive resolution (default: on for software rasterisers — see defaultSampleCount() — off on a GPU; the
  /// environment variable SHAPECAST_ADAPTIVE_RESOLUTION=0/1 overrides the default): interactive frames (a paint
  /// within kIdleRestoreMs of the previous one) render the background and mesh into an offscreen framebuffer of
  /// AdaptiveResolution::scale() times the widget's pixel size and stretch it onto the widget (linear filter);
  /// the scale follows the measured paint time (glFinish() at the end of each paint) against kPaintBudgetMs.
  /// Once nothing has been painted for kIdleRestoreMs the view repaints itself at full resolution. Needs a
  /// single-sampled widget framebuffer; with multisampling frames are always full resolution. Adaptive resolution
  /// also enables the interactive proxy (setInteractiveProxy()); the scale is tracked separately for frames of the
  /// mesh and of its proxy.
  void setAdaptiveResolution(bool on);
  [[nodiscard]] bool adaptiveResolution() const { return m_adaptive; }
  /// Replaces kPaintBudgetMs for this viewport (ms > 0; e.g. tests, or a client that must leave time for other
  /// work) and starts again from full resolution.
  void setPaintBudget(double ms) {
    m_resolution = AdaptiveResolution(ms);
    m_proxyResolution = AdaptiveResolution(ms);
  }
  /// The default of setAdaptiveResolution() for new viewports (probed once per process, see defaultSampleCount()).
  static bool defaultAdaptiveResolution();

  /// Positions the GPU path computes for the current Z, read back through transform feedback (3·#V floats, in
  /// the coordinates given to setMesh()); empty without a basis, coefficients, context or GPU path support.
  /// For tests and diagnostics (synchronous).
  [[nodiscard]] std::vector<float> gpuReconstructedPositions();
  /// The positions the CPU uses for picking (3·#V floats, in the coordinates given to setMesh()); on the GPU
  /// path they are reconstructed on the CPU first.
  [[nodiscard]] std::vector<float> hostPositions();

  /// Sets the vertices shown as handle (orange-red) and anchors (blue). Indices outside [0, #V) are dropped;
  /// the rest are sorted and de-duplicated. A vertex in both sets shows as a handle. Emits nothing.
  void setSelection(std::vector<int> handles, std::vector<int> anchors);
  [[nodiscard]] const std::vector<int>& handles() const { return m_handles; }
  [[nodiscard]] const std::vector<int>& anchors() const { return m_anchors; }

  /// Chooses what a left drag does; ends a gesture in progress (a drag in progress emits dragFinished()).
  void setTool(ViewportTool tool);
  [[nodiscard]] ViewportTool tool() const { return m_tool; }

  /// Brush radius in widget (logical) pixels; clamped to ≥ 1.
  void setBrushRadius(double pixels);
  [[nodiscard]] double brushRadius() const { return m_brushRadius; }

  /// Whether the Drag tool may move the handle (e.g. while this peer holds the edit lock). When not allowed, a
  /// left press with the Drag tool emits nothing and shows `hint` over the view for kHintMilliseconds.
  /// Revoking it during a drag ends that drag with dragFinished().
  void setDragAllowed(bool allowed, const QString& hint = {});
  [[nodiscard]] bool dragAllowed() const { return m_dragAllowed; }
  /// The hint currently shown over the view, or an empty string.
  [[nodiscard]] QString visibleHint() const { return m_visibleHint; }

  /// Draws the triangle edges over the shaded mesh (a GL_LINE pass over a polygon-offset fill).
  void setWireframe(bool on);
  [[nodiscard]] bool wireframe() const { return m_wireframe; }

  [[nodiscard]] int vertexCount() const { return m_vertexCount; }
  /// How many times paintGL() has run (for timing harnesses: Qt 6 turns a repaint() less than one display frame
  /// after the previous composition into an update(), so a synchronous frame needs ~17 ms since the last one).
  [[nodiscard]] int paintCount() const { return m_paintCount; }
  [[nodiscard]] int triangleCount() const { return static_cast<int>(m_indices.size() / 3); }
  [[nodiscard]] const OrbitCamera& camera() const { return m_camera; }

  [[nodiscard]] QSize minimumSizeHint() const override;
  [[nodiscard]] QSize sizeHint() const override;

 public slots:
  /// Re-frames the camera on the mesh's current vertices, with the default view angles.
  void resetView();
  /// Same as resetView() (the name the View menu uses).
  void fitToView() { resetView(); }
  /// Releases the GL objects; safe to call more than once and without a context ever having existed.
  void cleanup();

 signals:
  /// The mesh was replaced or removed.
  void meshChanged();
  /// A handle-brush stroke ended; `handles` is the full handle set now shown (sorted, unique).
  void handlePainted(std::vector<int> handles);
  /// An anchor-brush stroke ended; `anchors` is the full anchor set now shown (sorted, unique).
  void anchorsPainted(std::vector<int> anchors);
  /// A handle drag began (the Drag tool, allowed, a non-empty handle, pressed on the mesh).
  void dragStarted();
  /// The pose of the handle since dragStarted(): x ↦ rotation·(x − c) + c + translation, c the handle centroid
  /// at the start of the drag, in the coordinates given to setMesh() (see DragGesture).
  void dragMoved(Eigen::Vector3d translation, Eigen::Matrix3d rotation);
  /// The drag ended (mouse released, tool changed, drag revoked or mesh replaced).
  void dragFinished();

 protected:
  void initializeGL() override;
  void paintGL() override;
  void resizeGL(int width, int height) override;
  void mousePressEvent(QMouseEvent* event) override;
  void mouseMoveEvent(QMouseEvent* event) override;
  void mouseReleaseEvent(QMouseEvent* event) override;
  void mouseDoubleClickEvent(QMouseEvent* event) override;
  void wheelEvent(QWheelEvent* event) override;

 private:
  enum class Gesture { None, Camera, Paint, Drag, Blocked };

  /// Milliseconds since `timer` was (re)started, which restarts it (for FrameTimes).
  static double lapMs(QElapsedTimer& timer);

  // GL side (mesh_viewport.cpp).
  void positionsChanged();
  void updateBounds();
  void dropBasis();
  void applyCoefficients();
  void ensureHostPositions();
  void ensureFullVertexData();
  void refreshProxyPositions();
  [[nodiscard]] bool gpuDrawing() const;
  void createMeshVaos();
  void createGpuObjects();
  void destroyGpuObjects();
  void setGpuUniforms();
  void rebuildTints();
  void uploadIfDirty();
  void drawBackground();
  int drawMesh(bool wireframe, bool proxy);
  [[nodiscard]] bool proxyMayDraw() const;
  [[nodiscard]] bool proxyAllowed() const;
  void markMoved();
  void updateProxySelection();
  void drawScene(double scale, bool proxy, bool finish);
  void drawOverlay();
  [[nodiscard]] DepthImage renderDepth();

  // Input side (mesh_viewport_input.cpp).
  void beginStroke();
  void paintDab(QPointF pos, bool erase);
  bool beginDrag(QPointF pos);
  void endGesture();
  void showHint(const QString& text);
  [[nodiscard]] std::vector<int>& brushSelection();

  OrbitCamera m_camera;

  // Host side. Positions are stored relative to m_origin (the bounding-box centre at setMesh()) so that float
  // precision is spent on the shape, not on its placement.
  Eigen::RowVector3d m_origin = Eigen::RowVector3d::Zero();
  std::vector<float> m_positions;             // 3·#V, relative to m_origin
  std::vector<float> m_normals;               // 3·#V
  std::vector<std::uint8_t> m_tints;          // 4·#V, RGBA (A = tint strength)
  std::vector<std::uint32_t> m_indices;       // 3·#F
  std::vector<std::uint32_t> m_proxyIndices;  // 3·#P (interactive proxy, mesh vertices) after m_indices in
                                              // m_indexBuffer, for the GPU path
  CompactProxy m_proxy;                       // the proxy's own vertices, for the CPU path
  int m_vertexCount = 0;
  bool m_vertexDataDirty = false;
  bool m_tintsDirty = false;
  bool m_indicesDirty = false;
  bool m_normalsStale = false;  // m_normals lag m_positions (left behind by proxy-only frames or the GPU path)
  bool m_proxyDataDirty = false;
  bool m_proxyTintsDirty = false;
  bool m_proxyIndicesDirty = false;
  std::vector<int> m_handles;
  std::vector<int> m_anchors;
  bool m_wireframe = false;

  // Reconstruction (mesh_viewport_gpu.cpp). K is stored padded to 4·⌈m/4⌉ columns (zeros), Z likewise (rows).
  spectral::RowMatrixXf m_basis;                // #V by 4G
  std::vector<float> m_rest;                    // 3·#V, relative to m_origin
  Eigen::MatrixXf m_coefficients;               // 4G by 3
  int m_basisColumns = 0;                       // m (0: no basis)
  spectral::SharedDisplayLevel m_displayLevel;  // the level setDisplayLevel() shows (nullptr: a plain mesh)
  float m_basisMaxRowNorm = 0.0f;               // max_i ‖K_i‖, bounds |K·Z| for the camera's near/far planes
  Eigen::Vector3f m_restLo = Eigen::Vector3f::Zero();
  Eigen::Vector3f m_restHi = Eigen::Vector3f::Zero();
  ReconstructionPath m_path = ReconstructionPath::Cpu;
  bool m_showingCoefficients = false;  // the picture is rest + K·Z (else m_positions as given)
  bool m_hostPositionsStale = false;   // m_positions lags rest + K·Z (GPU path)
  bool m_basisDirty = false;
  bool m_restDirty = false;
  std::optional<ReconstructionTimings> m_timings;
  FrameTimes m_frameTimes;
  bool m_profiling = false;
  bool m_adaptive = false;
  AdaptiveResolution m_resolution{kPaintBudgetMs};       // frames of the full mesh
  AdaptiveResolution m_proxyResolution{kPaintBudgetMs};  // frames of the interactive proxy
  bool m_moved = false;                                  // positions or camera changed since the last paint
  bool m_proxyShowsSelection = true;                     // each non-empty selection group has a proxy vertex
  QElapsedTimer m_sinceLastPaint;
  QTimer m_restoreTimer;  // repaints at full resolution after an interactive frame

  // Interaction.
  ViewportTool m_tool = ViewportTool::Orbit;
  double m_brushRadius = kDefaultBrushRadius;
  bool m_dragAllowed = true;
  QString m_dragHint;
  QString m_visibleHint;
  QTimer m_hintTimer;
  Gesture m_gesture = Gesture::None;
  QPoint m_lastMousePos;
  std::optional<QPointF> m_cursor;          // for the brush outline
  std::vector<ScreenPoint> m_strokePoints;  // projected at the start of a stroke
  std::unique_ptr<DragGesture> m_drag;

  // GL side (valid between initializeGL() and cleanup()).
  std::unique_ptr<QOpenGLShaderProgram> m_meshProgram;
  std::unique_ptr<QOpenGLShaderProgram> m_backgroundProgram;
  std::unique_ptr<QOpenGLFramebufferObject> m_pickFbo;
  std::unique_ptr<QOpenGLFramebufferObject> m_sceneFbo;  // reduced-resolution frames
  QOpenGLFunctions_3_3_Core* m_gl33 = nullptr;           // for glPolygonMode; owned by the context
  QOpenGLVertexArrayObject m_meshVao;
  QOpenGLVertexArrayObject m_backgroundVao;
  QOpenGLBuffer m_positionBuffer{QOpenGLBuffer::VertexBuffer};
  QOpenGLBuffer m_normalBuffer{QOpenGLBuffer::VertexBuffer};
  QOpenGLBuffer m_tintBuffer{QOpenGLBuffer::VertexBuffer};
  QOpenGLBuffer m_indexBuffer{QOpenGLBuffer::IndexBuffer};
  QOpenGLVertexArrayObject m_proxyVao;  // CompactProxy's buffers, drawn with m_meshProgram
  QOpenGLBuffer m_proxyPositionBuffer{QOpenGLBuffer::VertexBuffer};
  QOpenGLBuffer m_proxyNormalBuffer{QOpenGLBuffer::VertexBuffer};
  QOpenGLBuffer m_proxyTintBuffer{QOpenGLBuffer::VertexBuffer};
  QOpenGLBuffer m_proxyIndexBuffer{QOpenGLBuffer::IndexBuffer};
  // GPU reconstruction: its own program and VAO (rest positions at location 0, tints at 2, the same indices).
  std::unique_ptr<QOpenGLShaderProgram> m_reconstructProgram;
  QOpenGLVertexArrayObject m_gpuVao;
  QOpenGLBuffer m_restBuffer{QOpenGLBuffer::VertexBuffer};
  unsigned m_basisBuffer = 0;   // GL_TEXTURE_BUFFER storage of K
  unsigned m_basisTexture = 0;  // GL_RGBA32F view of it
  unsigned m_feedbackBuffer = 0;
  long long m_maxTextureBufferTexels = 0;
  bool m_glReady = false;
  int m_paintCount = 0;
};

}  // namespace sc::app
