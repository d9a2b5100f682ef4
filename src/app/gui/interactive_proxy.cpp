#include "app/gui/interactive_proxy.h"

#include "app/gui/mesh_viewport.h"
#include "model/mesh_proxy.h"

#include <memory>
#include <utility>

namespace sc::app {

InteractiveProxyBuilder::InteractiveProxyBuilder(MeshViewport* viewport, QObject* parent)
    : QObject(parent), m_viewport(viewport) {
  connect(viewport, &MeshViewport::meshChanged, this, [this] { ++m_generation; });
}

InteractiveProxyBuilder::~InteractiveProxyBuilder() {
  if (m_worker.joinable()) {
    m_worker.join();  // its queued finish() is dropped with this object
  }
}

void InteractiveProxyBuilder::build(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
  m_pending.reset();  // superseded, whatever it was
  if (F.rows() <= kMinTriangles || !m_viewport || !m_viewport->adaptiveResolution()) {
    return;
  }
  if (m_lastProxy.rows() > 0 && F.rows() == m_lastFaces.rows() && F == m_lastFaces) {
    m_viewport->setInteractiveProxy(m_lastProxy);
    emit proxyApplied(static_cast<int>(m_lastProxy.rows()));
    return;
  }
  if (m_running) {
    m_pending.emplace(V, F);
    m_pendingGeneration = m_generation;
    return;
  }
  start(V, F, m_generation);
}

void InteractiveProxyBuilder::start(Eigen::MatrixXd V, Eigen::MatrixXi F, unsigned generation) {
  if (m_worker.joinable()) {
    m_worker.join();  // finished: it queued finish() before returning
  }
  m_running = true;
  m_worker = std::thread([this, V = std::move(V), F = std::move(F), generation]() mutable {
    auto proxy = std::make_shared<Eigen::MatrixXi>(model::proxyTriangles(V, F, kProxyTriangles));
    // The faces move on to become m_lastFaces: no copy of F (24 MB at a million vertices) here or on the GUI thread.
    auto faces = std::make_shared<Eigen::MatrixXi>(std::move(F));
    QMetaObject::invokeMethod(
        this, [this, generation, faces, proxy] { finish(generation, std::move(*faces), *proxy); },
        Qt::QueuedConnection);
  });
}

void InteractiveProxyBuilder::finish(unsigned generation, Eigen::MatrixXi faces, const Eigen::MatrixXi& proxy) {
  m_running = false;
  m_lastFaces = std::move(faces);
  m_lastProxy = proxy;
  // A waiting build starts first (unless its mesh was replaced since), so that a slot of proxyApplied() that
  // calls build() only queues behind it.
  if (m_pending && m_pendingGeneration == m_generation) {
    auto [V, F] = std::move(*m_pending);
    m_pending.reset();
    start(std::move(V), std::move(F), m_pendingGeneration);
  }
  m_pending.reset();
  if (generation == m_generation && m_viewport) {
    m_viewport->setInteractiveProxy(proxy);
    emit proxyApplied(static_cast<int>(proxy.rows()));
  }
}

}  // namespace sc::app
