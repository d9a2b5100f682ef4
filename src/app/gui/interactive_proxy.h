#pragma once
// InteractiveProxyBuilder: gives a MeshViewport showing a dense mesh its interactive proxy (a coarse triangulation
// of the mesh's own vertices, model::proxyTriangles()), computed on a worker thread so that the window never
// waits for it.

#include "spectral/display_level.h"

#include <Eigen/Core>

#include <QObject>
#include <QPointer>

#include <memory>
#include <optional>
#include <thread>

namespace sc::app {

class MeshViewport;

/// Builds proxies for one viewport. After each MeshViewport::setMesh() (setDisplayLevel()) of a mesh with more than
/// kMinTriangles triangles, call build() with the same V and F (the same level): the proxy (about kProxyTriangles
/// triangles) is computed on a worker thread and handed to MeshViewport::setInteractiveProxy() on the GUI thread,
/// unless the viewport's mesh changed in the meantime (meshChanged() makes a build in flight stale). Nothing is built
/// while the viewport's adaptive resolution is off (the proxy would never be drawn). The same faces as the previous
/// build (e.g. a host that shows its mesh again), or the same shared level, get the previous proxy at once (it names
/// vertices only, so it stays valid). One build runs at a time; a build asked for while one runs waits for it (only the
/// latest waits; a stale one is dropped). The destructor waits for the build in flight (about 0.7 s at most for the
/// 100k-vertex, 201k-triangle dragon).
class InteractiveProxyBuilder : public QObject {
  Q_OBJECT
  Q_DISABLE_COPY_MOVE(InteractiveProxyBuilder)

 public:
  /// Meshes with more triangles get a proxy. shapecast-bench-viewport (llvmpipe, 2 cores, docs/benchmarks.md): a
  /// client frame of the 47k-triangle dragon takes 32.5 ms median, p90 38 ms, drawn in full and 24.3–24.8 ms, p90
  /// 28–29 ms, with a 20k proxy.
  static constexpr int kMinTriangles = 40000;
  /// Triangles of a proxy: on the 201k-triangle dragon a client frame measured 25–28 ms median, p90 28–32 ms, with
  /// 20k (the proxy's own vertex buffer; 60–75 ms with the mesh itself); a 12k proxy was no faster (the frame's
  /// fixed costs dominate: composition and swap, the stretch of the reduced frame).
  static constexpr int kProxyTriangles = 20000;

  /// Observes `viewport` (not owned; the builder may be its child).
  explicit InteractiveProxyBuilder(MeshViewport* viewport, QObject* parent = nullptr);
  ~InteractiveProxyBuilder() override;

  /// Starts (or queues) the proxy of (V, F), the mesh the viewport was just given; does nothing for a mesh with at
  /// most kMinTriangles triangles or without adaptive resolution, and applies the previous proxy at once when F is
  /// the previous build's. Copies V and F. Cost on the calling thread: the copies (and O(#F) to compare F).
  void build(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F);
  /// The same for a shared display level (MeshViewport::setDisplayLevel()): the worker reads its X̂' and F' in place
  /// and holds the level while it runs (and while the build waits); nothing is copied. The level last built is
  /// remembered without being held (a weak pointer). Cost on the calling thread: O(1).
  void build(const spectral::SharedDisplayLevel& level);
  /// Whether a build runs or waits.
  [[nodiscard]] bool busy() const { return m_running || m_pending.has_value(); }

 signals:
  /// A proxy of `triangles` triangles was handed to the viewport. A slot may call build().
  void proxyApplied(int triangles);

 private:
  /// One build's input: a copy of a plain mesh's V and F, or a shared level's, held while the build needs it.
  struct Job {
    std::shared_ptr<const Eigen::MatrixXd> V;
    std::shared_ptr<const Eigen::MatrixXi> F;
    std::weak_ptr<const spectral::DisplayLevel> level;  // expired or empty for a plain mesh
    bool plain = true;
  };
  void submit(Job job);
  void start(Job job, unsigned generation);
  void finish(unsigned generation, const Job& job, const Eigen::MatrixXi& proxy);
  void applyLast();

  QPointer<MeshViewport> m_viewport;
  unsigned m_generation = 0;  // bumped by every meshChanged()
  bool m_running = false;
  std::optional<Job> m_pending;
  unsigned m_pendingGeneration = 0;
  std::thread m_worker;
  // The input of the last proxy built (a plain mesh's faces, kept; a level, not held), and that proxy.
  std::shared_ptr<const Eigen::MatrixXi> m_lastFaces;
  std::weak_ptr<const spectral::DisplayLevel> m_lastLevel;
  Eigen::MatrixXi m_lastProxy;
};

}  // namespace sc::app
