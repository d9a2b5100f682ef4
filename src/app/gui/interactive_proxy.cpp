#include "app/gui/interactive_proxy.h"

#include "app/gui/mesh_viewport.h"
#include "model/mesh_proxy.h"

#include <utility>

namespace sc::app {

namespace {

// Whether `a` and `b` name the same level (the same owner; an expired `a` names none).
bool sameLevel(const std::weak_ptr<const spectral::DisplayLevel>& a, const spectral::SharedDisplayLevel& b) {
  return !a.expired() && !a.owner_before(b) && !b.owner_before(a);
}

}  // namespace

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
  if (m_lastProxy.rows() > 0 && m_lastFaces && F.rows() == m_lastFaces->rows() && F == *m_lastFaces) {
    applyLast();
    return;
  }
  submit(Job{std::make_shared<const Eigen::MatrixXd>(V), std::make_shared<const Eigen::MatrixXi>(F), {}, true});
}

void InteractiveProxyBuilder::build(const spectral::SharedDisplayLevel& level) {
  m_pending.reset();
  if (!level || level->level.F.rows() <= kMinTriangles || !m_viewport || !m_viewport->adaptiveResolution()) {
    return;
  }
  if (m_lastProxy.rows() > 0 && sameLevel(m_lastLevel, level)) {
    applyLast();
    return;
  }
  // Aliasing pointers: the job holds the level itself, and reads its arrays in place.
  submit(Job{std::shared_ptr<const Eigen::MatrixXd>(level, &level->level.restV),
             std::shared_ptr<const Eigen::MatrixXi>(level, &level->level.F), level, false});
}

void InteractiveProxyBuilder::applyLast() {
  m_viewport->setInteractiveProxy(m_lastProxy);
  emit proxyApplied(static_cast<int>(m_lastProxy.rows()));
}

void InteractiveProxyBuilder::submit(Job job) {
  if (m_running) {
    m_pending.emplace(std::move(job));
    m_pendingGeneration = m_generation;
    return;
  }
  start(std::move(job), m_generation);
}

void InteractiveProxyBuilder::start(Job job, unsigned generation) {
  if (m_worker.joinable()) {
    m_worker.join();  // finished: it queued finish() before returning
  }
  m_running = true;
  m_worker = std::thread([this, job = std::move(job), generation]() mutable {
    auto proxy = std::make_shared<Eigen::MatrixXi>(model::proxyTriangles(*job.V, *job.F, kProxyTriangles));
    job.V.reset();  // a plain mesh's copy of V goes now (on this thread); a level's pointer only lets go of it
    // Moved into the call, not copied: nothing of the job (a level) stays with this thread after it posts.
    auto done = std::make_shared<Job>(std::move(job));
    QMetaObject::invokeMethod(
        this,
        [this, generation, done = std::move(done), proxy = std::move(proxy)] { finish(generation, *done, *proxy); },
        Qt::QueuedConnection);
  });
}

void InteractiveProxyBuilder::finish(unsigned generation, const Job& job, const Eigen::MatrixXi& proxy) {
  m_running = false;
  // The faces of a plain mesh stay (to recognise them again); a level is remembered, not held.
  m_lastFaces = job.plain ? job.F : nullptr;
  m_lastLevel = job.level;
  m_lastProxy = proxy;
  // A waiting build starts first (unless its mesh was replaced since), so that a slot of proxyApplied() that
  // calls build() only queues behind it.
  if (m_pending && m_pendingGeneration == m_generation) {
    Job next = std::move(*m_pending);
    m_pending.reset();
    start(std::move(next), m_pendingGeneration);
  }
  m_pending.reset();
  if (generation == m_generation && m_viewport) {
    m_viewport->setInteractiveProxy(proxy);
    emit proxyApplied(static_cast<int>(proxy.rows()));
  }
}

}  // namespace sc::app
