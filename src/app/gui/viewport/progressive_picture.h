#pragma once
// ProgressivePicture: the full-resolution picture of a mesh too large to draw within one paint on a software
// rasteriser (llvmpipe runs the vertex stage on the calling thread: 0.41–0.57 s for the 2M triangles of the
// million-vertex dragon), drawn a slice of its triangles at a time into an offscreen target between paints, so that
// the GUI thread never stands still for the whole mesh. MeshViewport shows the picture once it is complete (a blit)
// and a stand-in until then. Slices drawn in the mesh's order over one depth buffer give a whole draw's pixels; with
// wireframe each slice draws its fill then its edges, which differs from all fills then all edges only where a later
// slice's fill ties an earlier edge's depth. A complete picture follows a change of tints alone (a brush dab) by
// redrawing over itself only the triangles whose tints changed (patchTints()). Context current for every call but
// key() and the queries.

#include "app/gui/viewport/scene_passes.h"

#include <Eigen/Core>

#include <QMatrix4x4>
#include <QSize>

#include <cstdint>
#include <memory>
#include <vector>

class QOpenGLFramebufferObject;
class QOpenGLFunctions_3_3_Core;

namespace sc::app {

class GpuReconstructor;
class ViewportBuffers;

class ProgressivePicture {
 public:
  /// Meshes with at least this many triangles are drawn this way (MeshViewport's default). The 201k-triangle
  /// 100k dragon draws within a paint (a full frame of 60–75 ms on llvmpipe, interactive frames through its proxy);
  /// the 871k-triangle 437k scan and the 2M-triangle million-vertex dragon do not.
  static constexpr int kDefaultMinimumTriangles = 400'000;
  /// Wall time one slice aims at, glFinish() included: the next slice's size follows the measured rate of the last
  /// slice of full size (at most twice that size), not of a picture's short last slice.
  static constexpr double kSliceBudgetMs = 25.0;
  /// The first slice of a picture when no rate is known yet (about 15 ms of llvmpipe's vertex stage here).
  static constexpr int kFirstSliceTriangles = 1 << 16;

  /// Everything a picture of the whole mesh depends on: equal keys, equal pictures.
  struct Key {
    unsigned shared = 0;    ///< ViewportBuffers::sharedVersion()
    unsigned tints = 0;     ///< ViewportBuffers::tintVersion()
    unsigned vertices = 0;  ///< ViewportBuffers::vertexVersion() on the CPU path (0 on the GPU path: not drawn)
    QMatrix4x4 view;
    QMatrix4x4 projection;
    QSize size;  ///< device pixels
    bool wireframe = false;
    Eigen::MatrixXf gpuZ;  ///< the GPU path's scaled Z (empty on the CPU path)
    /// Everything but the tints is equal: the same shape in the same view, so the same depth.
    [[nodiscard]] bool sameShape(const Key& b) const {
      return shared == b.shared && vertices == b.vertices && view == b.view && projection == b.projection &&
             size == b.size && wireframe == b.wireframe && gpuZ.rows() == b.gpuZ.rows() &&
             gpuZ.cols() == b.gpuZ.cols() && gpuZ == b.gpuZ;
    }
    friend bool operator==(const Key& a, const Key& b) { return a.tints == b.tints && a.sameShape(b); }
  };
  /// The key of `pass` (its camera, wireframe and Z) drawn from `buffers` into `size` device pixels. Cost: O(m).
  static Key key(const ViewportBuffers& buffers, const MeshPass& pass, QSize size);

  ProgressivePicture();
  ~ProgressivePicture();
  ProgressivePicture(const ProgressivePicture&) = delete;
  ProgressivePicture& operator=(const ProgressivePicture&) = delete;

  /// Whether the picture of `key` is complete (then blit() shows it).
  [[nodiscard]] bool completeFor(const Key& key) const { return m_complete && m_key == key; }
  /// Whether the complete picture shows `key`'s shape in its view, whatever the tints (its depth is `key`'s).
  [[nodiscard]] bool shapeCompleteFor(const Key& key) const { return m_complete && m_key.sameShape(key); }
  /// Whether the picture, complete or being drawn, is of `key`'s shape in its view, whatever the tints.
  [[nodiscard]] bool followsShape(const Key& key) const { return m_started && m_key.sameShape(key); }
  /// Whether slices of `key` are being drawn (started, not complete).
  [[nodiscard]] bool drawing(const Key& key) const { return m_started && !m_complete && m_key == key; }
  [[nodiscard]] bool drawing() const { return m_started && !m_complete; }
  [[nodiscard]] bool complete() const { return m_complete; }
  /// The key of the picture started last.
  [[nodiscard]] const Key& key() const { return m_key; }
  /// Starts the picture of `key` over (`triangles`: the mesh's); the next drawNext() clears the target first.
  void start(Key key, int triangles);
  /// Forgets the picture (e.g. the mesh went away): nothing is complete or drawing.
  void reset();

  /// Draws the next slice of the started picture into its target (created or resized as needed), waits for the
  /// rasteriser (glFinish) and sizes the next slice from the time it took; with `rest`, every triangle left (the
  /// picture completes at the cost of a whole draw at most). `pass` must match the started key.
  /// Returns whether the picture is now complete. Leaves the context's default framebuffer bound.
  bool drawNext(QOpenGLFunctions_3_3_Core& gl, ScenePasses& passes, ViewportBuffers& buffers, GpuReconstructor& gpu,
                MeshPass pass, bool rest = false);
  /// Brings the picture, complete or being drawn, to `key` when only the tints changed since it was started, without
  /// wireframe (whose fill is pushed back under its edges): redraws over the slices drawn so far, the depth test
  /// passing equal depths, just their triangles with a vertex whose tint changed (a brush dab's few hundred or
  /// thousand instead of 2M); later slices draw the new tints. So it equals a whole draw except where two triangles
  /// tie in depth. Returns whether the picture now follows `key`; false, the picture untouched, when the key differs
  /// otherwise or more than a quarter of the drawn triangles would be redrawn (starting over costs about as much).
  /// `pass` must match `key`; `buffers` uploaded. Cost: O(#V + #F) to find the triangles, plus their draw.
  bool patchTints(QOpenGLFunctions_3_3_Core& gl, ScenePasses& passes, ViewportBuffers& buffers, GpuReconstructor& gpu,
                  MeshPass pass, const Key& key);
  /// Copies the target (complete or not: the slices drawn so far) onto framebuffer `target`, which it leaves bound.
  /// Cost: one blit of the size's pixels.
  void blit(QOpenGLFunctions_3_3_Core& gl, unsigned target) const;
  /// The depth of the complete picture, read back (4 bytes per pixel; rows bottom-up as glReadPixels gives them):
  /// what ScenePasses::renderDepth() would render for the same key without wireframe, without drawing the mesh.
  /// Empty unless complete. Leaves the context's default framebuffer bound.
  [[nodiscard]] DepthImage readDepth(QOpenGLFunctions_3_3_Core& gl) const;
  /// The target as an image (for tests); null before the first slice.
  [[nodiscard]] QImage image() const;
  /// Releases the target (context current).
  void destroy();

  /// Slices drawn for the current picture, and pictures completed so far (for tests and the stall probe).
  [[nodiscard]] int slices() const { return m_slices; }
  [[nodiscard]] int completed() const { return m_completed; }
  /// readDepth() calls that read a complete picture, and patchTints() calls that patched one (for tests).
  [[nodiscard]] int depthReads() const { return m_depthReads; }
  [[nodiscard]] int patches() const { return m_patches; }
  /// Upper bound on a slice's triangles (tests: forces several slices on a small mesh); ≤ 0: none.
  void setSliceLimit(int triangles) { m_sliceLimit = triangles; }

 private:
  /// Binds the target (existing) with its viewport and the state the mesh pass expects (no blend, scissor, stencil
  /// or culling: a QPainter overlay may have left them on).
  void bindTarget(QOpenGLFunctions_3_3_Core& gl);

  std::unique_ptr<QOpenGLFramebufferObject> m_target;
  Key m_key;
  bool m_started = false;
  bool m_complete = false;
  int m_triangles = 0;  // the mesh's
  int m_next = 0;       // first triangle of the next slice
  int m_sliceTriangles = kFirstSliceTriangles;
  int m_sliceLimit = 0;
  int m_slices = 0;
  int m_completed = 0;
  mutable int m_depthReads = 0;
  int m_patches = 0;
  std::vector<std::uint8_t> m_tints;    // the tints the picture shows (ViewportBuffers::tints() at its first slice)
  std::vector<std::uint8_t> m_changed;  // patchTints(): per vertex, whether its tint changed (kept: no reallocation)
};

}  // namespace sc::app
