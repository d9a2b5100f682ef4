#pragma once
// PicturePresenter: when and how a view shows the progressive picture of a large mesh (ProgressivePicture): whether
// a still paint blits the complete picture, patches it first (new tints alone), stands the interactive proxy in, draws
// the rest of it or shows its slices so far; the slices between paints (one per turn of the event loop); the
// completion a stroke's press needs for picking; and what the window has shown since the mesh was set. The GL
// drawing is ProgressivePicture's; the view (MeshViewport) answers the Host questions. GUI thread only.

#include "app/gui/mesh_viewport_types.h"
#include "app/gui/viewport/lap_timer.h"
#include "app/gui/viewport/progressive_picture.h"
#include "app/gui/viewport/renderer_defaults.h"

#include <QTimer>

#include <optional>

class QOpenGLFunctions_3_3_Core;

namespace sc::app {

/// The GL objects a picture draws with: the view's passes and buffers (uploaded), its GPU path and the mesh pass of
/// its current camera, wireframe and Z.
struct PictureScene {
  QOpenGLFunctions_3_3_Core& gl;
  ScenePasses& passes;
  ViewportBuffers& buffers;
  GpuReconstructor& gpu;
  MeshPass pass;
};

class PicturePresenter {
 public:
  /// What the presenter needs from the view that owns it.
  class Host {
   public:
    Host() = default;
    Host(const Host&) = delete;
    Host& operator=(const Host&) = delete;

    /// Whether the view can draw pictures now: adaptive resolution on, GL 3.3 passes ready, single-sampled, a size.
    [[nodiscard]] virtual bool picturesPossible() const = 0;
    [[nodiscard]] virtual int pictureTriangles() const = 0;
    /// The key of the full picture of the current view and shape (the mesh's positions made current first).
    virtual ProgressivePicture::Key currentPictureKey() = 0;
    /// Whether a moving frame may draw the interactive proxy (then it stands in until the picture is complete).
    [[nodiscard]] virtual bool proxyMayDraw() const = 0;
    /// The scene to draw with, its vertex buffers uploaded first; context current.
    virtual PictureScene pictureScene() = 0;
    /// The GL functions alone (nothing uploaded), e.g. to read a complete picture's depth; context current.
    virtual QOpenGLFunctions_3_3_Core& pictureGl() = 0;
    /// Whether the window is exposed (slices wait while it is not; a paint resumes them).
    [[nodiscard]] virtual bool pictureExposed() const = 0;
    /// Makes the view's context current (false: none), and releases it.
    virtual bool makePictureCurrent() = 0;
    virtual void releasePictureContext() = 0;
    /// Whether the full mesh's vertex data lags a newer frame (a picture of it would be stale at once).
    [[nodiscard]] virtual bool pictureShapeLagging() const = 0;
    /// Schedules a repaint of the window.
    virtual void repaintPicture() = 0;

   protected:
    ~Host() = default;
  };

  /// What a still window paint of a large mesh does.
  enum class Paint {
    Picture,  ///< showed the picture (complete, or its slices so far)
    Proxy,    ///< the caller draws the interactive proxy (FramePolicy::standIn()) until the picture is complete
    Whole,    ///< the caller draws the whole mesh as usual
  };

  explicit PicturePresenter(Host& host);
  PicturePresenter(const PicturePresenter&) = delete;
  PicturePresenter& operator=(const PicturePresenter&) = delete;

  /// Meshes of at least `minimumTriangles` > 0 triangles are drawn progressively (0: never); `sliceLimit` > 0 caps
  /// a slice's triangles (tests). See MeshViewport::setProgressivePicture().
  void setMinimumTriangles(int minimumTriangles, int sliceLimit);
  /// Whether full pictures of the view's mesh are drawn in slices now.
  [[nodiscard]] bool active() const;

  /// A still window paint into `framebuffer` (context current): the complete picture of the current view (a blit),
  /// patched first when only the tints changed; until it is complete Proxy (the slices follow), or without a proxy
  /// the rest of the picture drawn now once the window has shown this mesh whole and the paint is not `interactive`
  /// (a brush stroke after an orbit, wireframe), Whole for an interactive one, else (a new mesh) the slices so far
  /// (drawing the first one now if none is). Records the upload and mesh stages in `times`.
  Paint show(unsigned framebuffer, bool interactive, StageClock& stages, FrameTimes& times);
  /// After every window paint: whether it showed the picture, and whether it drew the proxy.
  void windowPainted(bool shown, bool proxy);
  /// The mesh was set or removed: it has not been shown whole yet.
  void meshReplaced() { m_wholePictureShown = false; }
  /// Starts (or continues) the slices of the current picture, or repaints at once when it is complete (the idle
  /// restore after a moving frame).
  void continuePicture();
  /// The depth of the current shape and view for picking (context current), read from the picture, which is
  /// completed first if needed (then shown by a repaint); nullopt when pictures are not active or the view has
  /// wireframe (its fill is pushed back under the edges, so the picture's depth is not the surface's).
  std::optional<DepthImage> depthForPicking();
  /// Releases the picture's target (context current) and stops the slices.
  void destroy();

  /// The picture (its slices, completions, patches and depth reads, for tests).
  [[nodiscard]] const ProgressivePicture& picture() const { return m_picture; }
  /// Whether the complete picture is that of the current view and shape (what a still paint shows now).
  [[nodiscard]] bool current() { return m_picture.completeFor(m_host.currentPictureKey()); }

 private:
  /// ProgressivePicture::patchTints() to `key`. Returns whether the picture follows it.
  bool patch(const ProgressivePicture::Key& key);
  /// One slice of the picture being drawn (m_sliceTimer), then a repaint when it is complete. A picture made stale by
  /// a change is dropped, not restarted (the next still paint or the idle restore starts it).
  void drawSlice();

  Host& m_host;
  ProgressivePicture m_picture;
  QTimer m_sliceTimer;  // the next slice, after a turn of the event loop
  int m_minimumTriangles = RendererDefaults::progressiveMinimumTriangles();  // 0: never
  bool m_showingPartial = false;     // the window shows the slices so far: each slice repaints
  bool m_showingPicture = false;     // the window's latest paint showed the picture complete
  bool m_wholePictureShown = false;  // the window showed this mesh whole since it was set (not only proxy/slices)
};

}  // namespace sc::app
