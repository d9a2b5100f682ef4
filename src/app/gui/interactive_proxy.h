#pragma once
// InteractiveProxyBuilder: gives a MeshViewport showing a dense mesh its interactive proxy (a coarse triangulation
// of the mesh's own vertices, model::proxyTriangles()), computed on a worker thread so that the window never
// waits for it.

#include <Eigen/Core>

#include <QObject>
#include <QPointer>

#include <optional>
#include <thread>
#include <utility>

namespace sc::app {

class MeshViewport;

/// Builds proxies for one viewport. After each MeshViewport::setMesh() of a mesh with more than kMinTriangles
/// triangles, call build() with the same V and F: the proxy (about kProxyTriangles triangles) is computed on a
/// worker thread and handed to MeshViewport::setInteractiveProxy() on the GUI thread, unless the viewport's mesh
/// changed in the meantime (meshChanged() makes a build in flight stale). Nothing is built while the viewport's
/// adaptive resolution is off (the proxy would never be drawn). The same faces as the previous build (e.g. a host
/// that shows its mesh again) get the previous proxy at once (it names vertices only, so it stays valid). One build
/// runs at a time; a build asked for while one runs waits for it (only the latest waits; a stale one is dropped). The
/// destructor waits for the build in flight (about 0.7 s at most for the 100k-vertex, 201k-triangle dragon).
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
  /// Whether a build runs or waits.
  [[nodiscard]] bool busy() const { return m_running || m_pending.has_value(); }

 signals:
  /// A proxy of `triangles` triangles was handed to the viewport. A slot may call build().
  void proxyApplied(int triangles);

 private:
  void start(Eigen::MatrixXd V, Eigen::MatrixXi F, unsigned generation);
  void finish(unsigned generation, Eigen::MatrixXi faces, const Eigen::MatrixXi& proxy);

  QPointer<MeshViewport> m_viewport;
  unsigned m_generation = 0;  // bumped by every meshChanged()
  bool m_running = false;
  std::optional<std::pair<Eigen::MatrixXd, Eigen::MatrixXi>> m_pending;
  unsigned m_pendingGeneration = 0;
  std::thread m_worker;
  Eigen::MatrixXi m_lastFaces;  // the faces of the last proxy built, and that proxy
  Eigen::MatrixXi m_lastProxy;
};

}  // namespace sc::app
