#pragma once
// MeshViewport: an OpenGL 3.3 core view of one triangle mesh, with orbit/pan/zoom, a selection brush and a handle
// drag. The widget draws on a window surface (ViewportSurface, a QOpenGLWindow in a createWindowContainer()) and
// composes classes with one job each (src/app/gui/viewport/): ViewportBuffers (host arrays and GL
// buffers, one dirty mask), ShownLevel (the shared display level and its frame), CpuReconstructor and
// GpuReconstructor (the two paths of X̂' + K·Z: the spectral kernel and the vertex shader), FramePolicy (proxy and
// adaptive resolution of moving frames), PicturePresenter (a large mesh's still picture drawn in slices),
// ViewportInput (mouse gestures → intent signals such as handlePainted and dragMoved, which a controller maps to
// session calls) and PresenceOverlay (the other users' cameras and pointers, drawn with QPainter after the GL passes).
// The camera math lives in OrbitCamera, the normals in vertexNormals(), picking in vertex_picking.h.

#include "app/gui/mesh_viewport_types.h"
#include "app/gui/orbit_camera.h"
#include "app/gui/viewport/frame_policy.h"
#include "app/gui/viewport/lap_timer.h"
#include "app/gui/viewport/level_frames.h"
#include "app/gui/viewport/picture_presenter.h"
#include "app/gui/viewport/presence_overlay.h"
#include "app/gui/viewport/renderer_defaults.h"
#include "app/gui/viewport/scene_passes.h"
#include "app/gui/viewport/viewport_buffers.h"
#include "app/gui/viewport/viewport_input.h"
#include "app/gui/viewport/viewport_selection.h"
#include "app/gui/viewport/viewport_surface.h"
#include "spectral/display_level.h"

#include <Eigen/Core>

#include <QImage>
#include <QOpenGLFunctions>
#include <QString>
#include <QSurfaceFormat>
#include <QTimer>
#include <QVector3D>
#include <QWidget>

#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <vector>

class QOpenGLFunctions_3_3_Core;

namespace sc::app {

/// Renders a triangle mesh with area-weighted vertex normals, two-light Blinn–Phong shading over a vertical
/// gradient background, framed on its vertices; optionally with its edges drawn over it (wireframe) and with the
/// handle (orange-red) and anchor (blue) vertices tinted.
///
/// Mouse: see ViewportTool; a double click on the surface makes the point under the cursor the orbit pivot (and
/// centres it), off the surface it re-frames (resetView()). Brush picking is a real visibility test: at the start of
/// each stroke the mesh is rendered into an offscreen depth buffer that is read back, and only vertices within
/// brushRadius() pixels of the cursor whose depth matches the rendered surface are painted (projectToScreen()).
///
/// GL lifetime follows Qt's hellogl2: nothing GL happens in the constructor; GL objects are made when the surface's
/// context is (initializeSurface()) and released in cleanup(), which runs on QOpenGLContext::aboutToBeDestroyed and
/// in the destructor. Setters only update host-side data, mark it dirty and call update(); the paint uploads lazily.
///
/// The surface: the GL picture is a ViewportSurface (QOpenGLWindow) filling this widget through
/// QWidget::createWindowContainer(); the window re-sends its input events to this widget, so the handlers below get
/// both real pointer events and QTest events sent to the widget. update() and repaint() (hiding QWidget's) repaint
/// the surface; grabFramebuffer() renders a frame offscreen, as QOpenGLWidget's did; frameSwapped() follows each
/// swap of the window.
///
/// Multisampling, reconstruction path and adaptive resolution start from RendererDefaults (none, CPU and on for a
/// software rasteriser such as Mesa llvmpipe). Deformation frames come either as positions (setPositions*(): a plain
/// mesh) or, after setDisplayLevel(), as coefficients Z (showFrame()), reconstructed on the path chosen by
/// setReconstructionPath(); the GPU path shades with face normals (see GpuReconstructor). Host positions for picking
/// and dragging follow lazily, only when a gesture starts. Moving frames may be lightened (FramePolicy: reduced
/// resolution, interactive proxy) and the view redraws itself in full once idle. frameTimes() reports each frame.
///
/// Signals carry std::vector / Eigen values and are meant for direct (same-thread) connections.
class MeshViewport : public QWidget,
                     protected QOpenGLFunctions,
                     private ViewportInput::View,
                     private ViewportSurface::Client,
                     private PicturePresenter::Host {
  Q_OBJECT
  Q_DISABLE_COPY_MOVE(MeshViewport)

 public:
  // The defaults of a new viewport (surface format, samples, path, adaptive resolution) are RendererDefaults'; the
  // brush and hint constants ViewportInput's; the frame budget and idle delay FramePolicy's.

  /// Multisample count of this widget's framebuffer; takes effect only before the widget is first shown.
  void setSampleCount(int samples);
  [[nodiscard]] int sampleCount() const { return m_surface->format().samples(); }

  // --- the surface (QOpenGLWidget's calls, kept for the callers)
  /// Schedules a repaint of the surface (hides QWidget::update(): this widget itself shows nothing).
  void update();
  /// Paints the surface now when it is exposed, else schedules it (hides QWidget::repaint()).
  void repaint();
  /// Renders a frame (a paint, as on screen) into an offscreen framebuffer and returns it (device pixels, RGB32);
  /// a null image without a GL context.
  [[nodiscard]] QImage grabFramebuffer();
  /// Makes the surface's context current (creating it and running the GL initialisation at the first call when
  /// the window exists), and releases it.
  void makeCurrent();
  void doneCurrent();
  /// The surface's context (nullptr before the first paint or makeCurrent()).
  [[nodiscard]] QOpenGLContext* context() const { return m_surface->context(); }
  /// The window surface itself (e.g. tests that send events to the window).
  [[nodiscard]] ViewportSurface* surface() const { return m_surface; }

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

  /// A coarse triangulation of the current mesh's own vertices (model::proxyTriangles()) that moving frames draw
  /// instead of the mesh's triangles with adaptive resolution on (a software rasteriser pays per triangle at any
  /// pixel scale); the rules are FramePolicy's (a proxy frame also needs a vertex of each non-empty selection group
  /// in the proxy, so that a small selection never vanishes). It has its own vertices (CompactProxy) and follows
  /// every deformation; on the CPU path, while proxy frames are possible, showFrame() reconstructs only the proxy's
  /// vertices (a tenth of the work for the 100k dragon) and the mesh's follow lazily (CpuReconstructor).
  /// @param[in] triangles  #P by 3 indices into the current mesh's vertices; empty removes the proxy.
  /// setMesh() and clearMesh() remove it. An index out of range is a programming error (asserted; in release builds
  /// the call is ignored and the previous proxy stays).
  void setInteractiveProxy(const Eigen::MatrixXi& triangles);
  /// Triangles of the interactive proxy (0: none).
  [[nodiscard]] int proxyTriangleCount() const { return static_cast<int>(m_buffers.proxyIndices().size() / 3); }

  /// The one-way frame path (docs/architecture.md): shows `level`'s rest mesh and faces and frames the camera on it,
  /// like setMesh(). The viewport HOLDS the shared level: both reconstruction paths read its K in place (the CPU
  /// kernel directly, the GPU path's texture is filled from it at upload time, padded to 4·⌈m/4⌉ columns, only
  /// once the GPU path draws), and the vertex buffers are filled from its DisplayGeometry (rest positions relative
  /// to its origin, normals, faces, box; computed with the level, off the GUI thread) with no copy here: the first
  /// CPU frame writes its own positions and normals. Cost: O(#V) for the selection tints, O(m) else; the upload in
  /// the next paint. Nothing moves until showFrame(). nullptr, or a level without vertices or faces: clearMesh().
  /// A level without basis columns shows as a plain mesh.
  void setDisplayLevel(spectral::SharedDisplayLevel level);
  /// Shows one frame of the displayed level, X̂' + K·frame.Z (the rest shape for an empty Z), on the current path
  /// (the per-frame call of a client). Ignored without a level or for a Z that is not m by 3, and a Z already shown
  /// (a still frame) neither reconstructs nor repaints.
  /// CPU path: reconstructs, recomputes normals and bounds now (O(#V·m + #F)), uploads in paintGL(); while a frame
  /// may draw the interactive proxy, only the proxy's vertices (O(#P·m + #T)), the mesh's following when needed
  /// (see setInteractiveProxy()). GPU path: O(m) here; paintGL() uploads 12·m bytes of uniforms and the vertex
  /// shader does the rest.
  /// Returns whether the picture changed (a repaint follows).
  bool showFrame(const spectral::DisplayFrame& frame);
  /// The level setDisplayLevel() shows (nullptr: a plain mesh, or none).
  [[nodiscard]] const spectral::SharedDisplayLevel& displayLevel() const { return m_frames.shown().level(); }
  /// Whether the vertex buffers show the display level's own arrays (positions, normals, faces: setDisplayLevel()
  /// copies none) rather than arrays of their own (a CPU frame of the full mesh writes its own). For tests.
  [[nodiscard]] bool showsLevelArrays() const { return m_buffers.sharesLevel(); }
  /// Whether frames are reconstructed here (a display level with basis columns is shown).
  [[nodiscard]] bool hasReconstructionBasis() const { return !m_frames.shown().empty(); }

  /// Chooses where showFrame() frames are reconstructed (default RendererDefaults::reconstructionPath()). Gpu falls
  /// back to Cpu where the context cannot do it (GpuReconstructor::available()).
  void setReconstructionPath(ReconstructionPath path);
  [[nodiscard]] ReconstructionPath reconstructionPath() const { return m_frames.path(); }
  /// Whether the GPU path can draw the current basis (false until the GL context exists).
  [[nodiscard]] bool gpuReconstructionAvailable() const { return m_frames.gpuAvailable(); }

  /// Stage times of the latest frame (see FrameTimes); the host stages are those of the latest position change.
  [[nodiscard]] const FrameTimes& frameTimes() const { return m_frameTimes; }
  /// An observer called at the end of each GL stage of paintGL() (upload, background, mesh, overlay) with the
  /// context current, before the stage's time is taken; e.g. shapecast-bench-viewport's glFinish() that attributes
  /// the rasteriser's work to its stage. Empty: none (the default).
  void setStageHook(std::function<void()> hook) { m_stages.setHook(std::move(hook)); }

  /// Adaptive resolution (default RendererDefaults::adaptiveResolution()): interactive frames render into an
  /// offscreen framebuffer of AdaptiveResolution::scale() times the widget's pixels, stretched onto it, the scale
  /// following the measured paint time against FramePolicy::kPaintBudgetMs; the idle repaint is full resolution.
  /// Needs a single-sampled framebuffer. Also enables the interactive proxy (setInteractiveProxy()).
  void setAdaptiveResolution(bool on);
  [[nodiscard]] bool adaptiveResolution() const { return m_policy.adaptive(); }
  /// Replaces FramePolicy::kPaintBudgetMs for this viewport (ms > 0; e.g. tests, or a client that must leave time for
  /// other work) and starts again from full resolution.
  void setPaintBudget(double ms) { m_policy.setPaintBudget(ms); }

  /// Meshes of at least `minimumTriangles` > 0 triangles (default RendererDefaults::progressiveMinimumTriangles()) have
  /// their full-resolution picture drawn in slices between paints while adaptive resolution is on and the window is
  /// single-sampled (PicturePresenter says what each paint shows meanwhile, ProgressivePicture how slices and patches
  /// are drawn); a change of the view, the shape, the wireframe or the size makes the picture stale. grabFramebuffer()
  /// always draws the whole mesh. `sliceLimit` > 0 caps a slice's triangles (tests). Off by default on a GPU.
  void setProgressivePicture(int minimumTriangles, int sliceLimit = 0);
  /// Picking (a brush stroke's or a drag's start) reads the complete picture's depth when it shows the current shape
  /// and view (no wireframe; tints aside) instead of drawing the mesh's depth again.
  /// The picture (its slices, completions and depth reads, for tests) and its image as drawn (context made current).
  [[nodiscard]] const ProgressivePicture& progressivePicture() const { return m_pictures.picture(); }
  [[nodiscard]] QImage progressivePictureImage();
  /// Whether the complete picture is that of the current view and shape (what a still paint shows now).
  [[nodiscard]] bool progressivePictureCurrent() { return m_pictures.current(); }

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
  [[nodiscard]] const std::vector<int>& handles() const { return m_selection.handles(); }
  [[nodiscard]] const std::vector<int>& anchors() const { return m_selection.anchors(); }

  /// Chooses what a left drag does; ends a gesture in progress (a drag in progress emits dragFinished()).
  void setTool(ViewportTool tool);
  [[nodiscard]] ViewportTool tool() const { return m_input.tool(); }

  /// Brush radius in widget (logical) pixels; clamped to ≥ 1.
  void setBrushRadius(double pixels);
  [[nodiscard]] double brushRadius() const { return m_input.brushRadius(); }

  /// Whether the Drag tool may move the handle (e.g. while this peer holds the edit lock). When not allowed, a
  /// left press with the Drag tool emits nothing and shows `hint` over the view for ViewportInput::kHintMilliseconds.
  /// Revoking it during a drag ends that drag with dragFinished().
  void setDragAllowed(bool allowed, const QString& hint = {});
  [[nodiscard]] bool dragAllowed() const { return m_input.dragAllowed(); }
  /// The hint currently shown over the view, or an empty string.
  [[nodiscard]] QString visibleHint() const { return m_input.visibleHint(); }

  /// Draws the triangle edges over the shaded mesh (a GL_LINE pass over a polygon-offset fill).
  void setWireframe(bool on);
  [[nodiscard]] bool wireframe() const { return m_wireframe; }

  [[nodiscard]] int vertexCount() const override { return m_vertexCount; }
  /// How many frames were painted (on the window, or offscreen by grabFramebuffer()); for timing harnesses. The
  /// window system's exposes paint too (another window uncovering this one).
  [[nodiscard]] int paintCount() const { return m_paintCount; }
  /// How many repaints this viewport asked for (update(), repaint()): paintCount() without the window system's
  /// exposes; for tests of what the application redraws.
  [[nodiscard]] int repaintRequestCount() const { return m_repaintRequests; }
  [[nodiscard]] int triangleCount() const { return static_cast<int>(m_buffers.indices().size() / 3); }
  [[nodiscard]] const OrbitCamera& camera() const { return m_camera; }

  // --- presence (issue 15): coordinates here are the mesh's own (as given to setMesh / the level's rest positions)
  using LocalView = ViewportLocalView;
  [[nodiscard]] LocalView localView() const;
  /// The other users' markers to draw (PresenceOverlay), in mesh coordinates; repaints.
  void setPresenceMarkers(std::vector<PresenceMarker> markers);
  /// The markers as drawn (viewport coordinates: the mesh's less the origin).
  [[nodiscard]] const std::vector<PresenceMarker>& presenceMarkers() const { return m_presence.markers(); }
  /// Moves the camera to look from `eye` at `target` (mesh coordinates; OrbitCamera::lookAt). Emits nothing.
  void lookFrom(const QVector3D& eye, const QVector3D& target);
  /// Recomputes the pointer's surface point as if the mouse were at `position` (widget pixels); nullopt: off.
  void setPointer(std::optional<QPointF> position);

  [[nodiscard]] QSize minimumSizeHint() const override;
  [[nodiscard]] QSize sizeHint() const override;

  // --- camera (mesh_viewport_camera.cpp): the view habits of View → Standard Views, Up Axis, Trackball
  /// Re-frames the camera on the mesh's current vertices, turned to `view` (nullopt: keeping the orientation).
  void showView(std::optional<StandardView> view);
  /// The up axis of the camera (OrbitCamera::setUpAxis): re-frames from the Home view.
  void setUpAxis(UpAxis axis);
  [[nodiscard]] UpAxis upAxis() const { return m_camera.upAxis(); }
  /// Turntable or trackball rotation for orbit drags (OrbitCamera::setRotationMode).
  void setRotationMode(RotationMode mode) { m_camera.setRotationMode(mode); }
  [[nodiscard]] RotationMode rotationMode() const { return m_camera.rotationMode(); }
  /// Makes the surface point under `position` (widget pixels) the orbit pivot (OrbitCamera::setPivot): true, or
  /// false (nothing changes) when no surface is under it. Emits cameraMovedByUser() when it moved.
  bool setPivotAt(QPointF position);

 public slots:
  /// Re-frames the camera on the mesh's current vertices, with the default view angles (showView(Home)).
  void resetView();
  /// Re-frames the camera on the mesh's current vertices keeping its orientation (showView(nullopt)).
  void fitToView() { showView(std::nullopt); }
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
  /// The user orbited, panned or zoomed (not lookFrom(), not a re-frame).
  void cameraMovedByUser();
  /// A frame was swapped onto the window (QOpenGLWindow::frameSwapped()).
  void frameSwapped();

 protected:
  void mousePressEvent(QMouseEvent* event) override;
  void mouseMoveEvent(QMouseEvent* event) override;
  void mouseReleaseEvent(QMouseEvent* event) override;
  void mouseDoubleClickEvent(QMouseEvent* event) override;
  void wheelEvent(QWheelEvent* event) override;
  void leaveEvent(QEvent* event) override;

 private:
  // ViewportSurface::Client.
  void initializeSurface() override;
  void paintSurface(unsigned framebuffer) override;
  void resizeSurface(int width, int height) override;

  // ViewportInput::View.
  [[nodiscard]] QSize viewSize() const override { return size(); }
  [[nodiscard]] double pixelRatio() const override { return devicePixelRatioF(); }
  void requestRepaint() override { update(); }
  OrbitCamera& viewCamera() override { return m_camera; }
  std::span<const float> pickPositions() override;
  DepthImage renderDepth() override;
  std::vector<int>& selection(bool handles) override { return m_selection.group(handles); }
  void selectionEdited() override;
  void cameraMoved() override {
    markMoved();
    emit cameraMovedByUser();
  }
  [[nodiscard]] unsigned shapeVersion() const override { return m_shapeVersion; }

  // PicturePresenter::Host (mesh_viewport_render.cpp; proxyMayDraw() in mesh_viewport.cpp).
  [[nodiscard]] bool picturesPossible() const override;
  [[nodiscard]] int pictureTriangles() const override { return triangleCount(); }
  ProgressivePicture::Key currentPictureKey() override;
  [[nodiscard]] bool proxyMayDraw() const override;
  PictureScene pictureScene() override;
  QOpenGLFunctions_3_3_Core& pictureGl() override { return *m_gl33; }
  [[nodiscard]] bool pictureExposed() const override { return m_surface->isExposed(); }
  bool makePictureCurrent() override { return m_surface->makeContextCurrent(); }
  void releasePictureContext() override { doneCurrent(); }
  [[nodiscard]] bool pictureShapeLagging() const override { return m_frames.fullVertexDataLagging(); }
  void repaintPicture() override { update(); }

  /// Paints into `framebuffer`: the window's (`window`), or a grab's (always the whole mesh at full resolution).
  void paint(unsigned framebuffer, bool window);

  void positionsGiven();
  void updateBounds();
  /// The camera's scene bounds (relative to the origin) and a repaint; `conservative`: a lagging frame's box.
  void setSceneBounds(const QVector3D& lo, const QVector3D& hi, bool conservative);
  /// The camera's bounds become exact where they were conservative and the positions are current now (a gesture or
  /// a paint of the full mesh made them so). Returns whether they changed. Cost: O(#V) then, else O(1).
  bool tightenBounds();
  void applyFrame();
  void rebuildTints();
  void markMoved();
  [[nodiscard]] MeshPass meshPass(bool wireframe, bool proxy) const;
  [[nodiscard]] const spectral::QuantizedBasis* gpuBasis() const;  // K when the GPU path draws, else nullptr
  [[nodiscard]] QSize pixelSize() const;

  OrbitCamera m_camera;
  // Positions are stored relative to m_origin (the bounding-box centre at setMesh()) so that float precision is
  // spent on the shape, not on its placement.
  Eigen::RowVector3d m_origin = Eigen::RowVector3d::Zero();
  int m_vertexCount = 0;
  ViewportBuffers m_buffers;
  LevelFrames m_frames;
  FramePolicy m_policy;
  QTimer m_restoreTimer;        // repaints at full resolution after an interactive frame
  PicturePresenter m_pictures;  // the progressive picture of a large mesh
  ViewportInput m_input;
  ViewportSelection m_selection;
  bool m_proxyShowsSelection = true;  // m_selection.shownBy(the proxy), cached
  unsigned m_shapeVersion = 0;        // bumped by every change of the drawn positions (updateBounds())
  bool m_boundsConservative = false;  // the camera has LevelFrames' conservative bounds of a lagging frame
  bool m_wireframe = false;
  FrameTimes m_frameTimes;
  StageClock m_stages;
  PresenceOverlay m_presence;
  std::optional<QVector3D> m_pointer;  // viewport coordinates
  float m_sceneDiagonal = 1.0f;        // of the scene bounds (the presence markers' scale)

  // GL side (valid between initializeSurface() and cleanup()).
  ViewportSurface* m_surface = nullptr;  // owned by m_container
  QWidget* m_container = nullptr;        // createWindowContainer(m_surface), a child of this widget
  ScenePasses m_passes;
  QOpenGLFunctions_3_3_Core* m_gl33 = nullptr;  // owned by the context
  int m_paintCount = 0;
  int m_repaintRequests = 0;
};

}  // namespace sc::app
