// HostController: preparation, the SessionHost and its local user (lock, constraints, poses), the restoring of a
// saved session's state, the host's display (its full level once, a frame per new Z) and its figures.
#include "app/gui/host_controller.h"

#include "app/common/password_memory.h"
#include "app/gui/host_preparation.h"
#include "app/gui/saved_constraints.h"
#include "app/gui/vertex_id_lists.h"
#include "model/decimating_level_builder.h"
#include "model/session_file.h"
#include "session/engine/constraint_work.h"
#include "session/engine/host_model.h"
#include "session/net/host_datagram_channel.h"
#include "session/net/relay_publisher.h"
#include "session/net/session_host.h"
#include "spectral/spectral_deformer.h"

#include <QLocale>

#include <algorithm>
#include <optional>
#include <span>
#include <utility>

namespace sc::app {

namespace {

/// A host displays the full level: its displayed ids are full ids, and back.
spectral::DisplayVertexIds displayedIds(const spectral::FullVertexIds& full) {
  spectral::DisplayVertexIds ids;
  ids.reserve(full.size());
  for (const spectral::FullVertexId id : full) ids.emplace_back(id.value);
  return ids;
}

spectral::ConstraintSet constraintSet(const spectral::FullVertexIds& handle, const spectral::FullVertexIds& anchors) {
  spectral::ConstraintSet set;
  set.handles.push_back({intIds<spectral::FullVertexTag>(handle)});
  set.anchors = intIds<spectral::FullVertexTag>(anchors);
  return set;
}

}  // namespace

HostController::HostController(QObject* parent) : SessionController(parent) {}

HostController::~HostController() {
  if (m_preparation) {
    m_preparation->cancel();
    m_preparation->join();
  }
  // At most the broker's connect and request timeouts (2 + 2 s per URL) when it never answers; milliseconds usually.
  if (m_relayConnect.joinable()) m_relayConnect.join();
  delete m_relay;  // it follows m_host
  m_relay = nullptr;
  if (m_host != nullptr) {
    m_host->disconnect(this);
    m_host->shutdown();
  }
}

// ---------------------------------------------------------------------------------------------------- starting

bool HostController::host(const HostSettings& settings, PortReservation port) {
  if (state() != State::Idle) return false;
  m_settings = settings;
  changeState(State::Preparing);
  // The port first: a busy one is an error now, not after seconds of basis computation.
  if (!port.holds()) {
    QString error;
    std::optional<PortReservation> taken = PortReservation::take(settings.port, &error);
    if (!taken) {
      forgetPassword(m_settings.password);  // nothing will derive a key from it
      fail(error);
      return false;
    }
    port = std::move(*taken);
  }
  m_port = std::move(port);
  emit progress(0, tr("Loading %1").arg(settings.meshPath));
  m_preparation = std::make_unique<HostPreparation>();
  m_preparation->start(
      settings, this, [this](int percent, const QString& what) { emit progress(percent, what); },
      [this](const std::shared_ptr<PreparedHost>& prepared) { finishPreparation(prepared); });
  return true;
}

void HostController::finishPreparation(const std::shared_ptr<PreparedHost>& prepared) {
  m_preparation->join();
  if (state() != State::Preparing) return;  // cancelled or left meanwhile
  if (prepared->cancelled) {
    fail(tr("Cancelled."));
    return;
  }
  if (!prepared->error.isEmpty() || !prepared->model || !prepared->level) {
    fail(tr("Could not host %1: %2").arg(m_settings.meshPath, prepared->error));
    return;
  }
  m_model = prepared->model;
  m_saved = prepared->saved;
  session::SessionHostOptions options;
  options.levelBuilder = session::LevelBuilder{model::levelTargetList, model::decimatedLevel};
  options.tcpPort = m_settings.port;
  options.password = m_settings.password;
  options.hostName = m_settings.name.isEmpty() ? QStringLiteral("host") : m_settings.name;
  options.maxEditors = m_settings.editors;
  if (m_saved) options.deformer.mode = m_saved->mode;
  m_host = new session::SessionHost(m_model, options, this);
  m_port.release();  // SessionHost::start() listens on it now
  QString error;
  const bool started = m_host->start(&error);  // derives the password's key
  forgetPassword(options.password);
  forgetPassword(m_settings.password);
  if (!started) {
    fail(tr("Could not host on TCP port %1: %2").arg(m_settings.port).arg(error));
    return;
  }
  connect(m_host, &session::SessionHost::frameSent, this, &HostController::onFrame);
  connect(m_host, &session::SessionHost::lockChanged, this, &HostController::onLockChanged);
  connect(m_host, &session::SessionHost::editHistoryChanged, this, &HostController::editLogChanged);
  connect(m_host, &session::SessionHost::peersChanged, this, &HostController::peersChanged);
  // No statsChanged per StatsReport: the once-a-second statsChanged shows the latest reports, so the docks redraw
  // once a second however many members report (each redraw composes the whole window: issue 16, idle CPU).
  connect(m_host, &session::SessionHost::presenceReceived, this, &HostController::presenceReceived);
  showLevel(std::move(prepared->level));
  showFrame({m_host->currentFrame(), m_host->coefficients().cast<float>()});
  emit progress(100, tr("Hosting"));
  changeState(State::Live);
  emit meshChanged();
  emit peersChanged();
  emit lockChanged();
  emit hostingStarted(m_host->tcpPort());
  if (m_settings.relay) startRelay();
  if (m_saved) restoreSavedSession();
}

void HostController::startRelay() {
  session::RelayPublisherOptions options;
  options.nats.url = m_settings.relay->url;
  options.nats.user = m_settings.relay->user;
  options.nats.password = m_settings.relay->password;
  options.nats.caFile = m_settings.relay->caFile;
  options.nats.name = QStringLiteral("shapecast host");
  options.sessionId = m_settings.relay->sessionId;
  m_settings.relay->password.clear();  // the publisher keeps its copy (cnats reconnects with it)
  emit progress(100, tr("Hosting; connecting to the relay at %1").arg(options.nats.url));
  m_relayConnect = std::thread([this, options] {
    auto link = std::make_shared<session::RelayBrokerLink>(session::RelayPublisher::connectToBroker(options));
    // Only a queued call touches `this`; the destructor joins this thread, so the object is alive here.
    QMetaObject::invokeMethod(
        this, [this, link, options] { finishRelay(std::move(*link), options); }, Qt::QueuedConnection);
  });
}

void HostController::finishRelay(session::RelayBrokerLink link, const session::RelayPublisherOptions& options) {
  if (m_relayConnect.joinable()) m_relayConnect.join();     // it has posted this call: it is ending
  if (m_host == nullptr || state() != State::Live) return;  // hosting ended meanwhile: the link closes here
  auto* relay = new session::RelayPublisher(*m_host, options, this);
  QString error;
  if (!relay->start(std::move(link), &error)) {
    delete relay;
    // The editors' session is up and unaffected: it goes on, without the relay (as with the command line).
    emit failed(tr("Hosting without the relay through NATS: %1. Editors join as usual; viewers through NATS will not "
                   "see this session until you host again with working relay settings.")
                    .arg(error));
    return;
  }
  m_relay = relay;
  emit progress(100, tr("Hosting; relaying through %1").arg(options.nats.url));
}

std::optional<session::RelayAudienceSummary> HostController::relayAudience() const {
  if (m_relay == nullptr) return std::nullopt;
  return m_relay->audience();
}

void HostController::restoreSavedSession() {
  // The shape and the edit history first: they need no lock (nobody has joined yet).
  const Eigen::MatrixXd Z = m_saved->Z.size() > 0 ? m_saved->Z : Eigen::MatrixXd::Zero(m_model->rowCount(), 3);
  std::vector<session::EditStep> steps;
  steps.reserve(m_saved->steps.size());
  for (const model::SavedEditStep& saved : m_saved->steps) {
    steps.push_back({0, session::kNoPeer, saved.author, saved.delta,
                     saved.undone ? session::kHostPeer : session::kNoPeer, saved.undone});
  }
  if (!m_host->restoreEdits(Z, steps)) {
    emit failed(tr("The saved shape could not be restored (its coefficients do not fit this basis)."));
    emit savedSessionRestored();
    return;
  }
  showFrame({m_host->currentFrame(), Z.cast<float>()});
  emit editLogChanged();
  const std::optional<model::SavedConstraints> current = m_saved->current;
  if (!current) {
    emit savedSessionRestored();
    return;
  }
  // Then the host user's constraints, as the lock holder: granted at once when nobody holds the lock (a fresh
  // host); otherwise set when it is granted.
  const auto restore = [this, current] {
    const HostConstraints constraints = toHostConstraints(*current);
    if (m_host->setConstraints(constraintSet(constraints.handle, constraints.anchors))) {
      editor().adopt(constraints, displayedIds(constraints.handle), displayedIds(constraints.anchors));
    } else {
      emit failed(tr("The saved handle and anchors could not be restored (the deformer refused them)."));
    }
    emit savedSessionRestored();
  };
  requestLock();
  if (canDrag()) {
    restore();
    return;
  }
  auto connection = std::make_shared<QMetaObject::Connection>();
  *connection = connect(this, &SessionController::lockChanged, this, [this, restore, connection] {
    if (!canDrag()) return;
    disconnect(*connection);
    restore();
  });
}

void HostController::onFrame() {
  const spectral::SharedDisplayLevel& level = displayLevel();
  const Eigen::MatrixXd& Z = m_host->coefficients();
  if (!level || Z.rows() != level->basisSize() || Z.cols() != 3) return;
  Eigen::MatrixXf Zf = Z.cast<float>();
  const Eigen::MatrixXf& shown = displayFrame().Z;
  if (shown.rows() == Zf.rows() && shown.cols() == Zf.cols() && shown == Zf) return;  // idle refresh
  showFrame({m_host->currentFrame(), std::move(Zf)});
}

// ---------------------------------------------------------------------------------------------------- ending

void HostController::cancel() {
  if (state() != State::Preparing || !m_preparation) return;
  markCancelledByUser();
  m_preparation->cancel();  // finishPreparation() reports the cancellation once the worker stops
}

void HostController::stop() {
  m_port.release();
  delete m_relay;
  m_relay = nullptr;
  if (m_preparation) m_preparation->cancel();
  if (m_host != nullptr) m_host->shutdown();
}

// ---------------------------------------------------------------------------------------------------- lock, edits

void HostController::sendPresence(const session::Presence& presence) {
  if (state() == State::Live) m_host->setPresence(presence);
}

bool HostController::requestLock() { return state() == State::Live && m_host->requestLock(); }

bool HostController::release() { return m_host->releaseLock(); }

const session::LockClient* HostController::lockClient() const {
  return m_host != nullptr ? &m_host->localLock() : nullptr;
}

std::vector<session::PeerId> HostController::lockHolders() const {
  std::vector<session::PeerId> out;
  if (state() != State::Live) return out;
  for (const session::LockHolding& lease : m_host->lockHolders()) out.push_back(lease.peer);
  return out;
}

std::vector<session::PeerId> HostController::lockQueue() const {
  if (state() != State::Live) return {};
  return {m_host->lockQueue().begin(), m_host->lockQueue().end()};
}

bool HostController::kick(session::PeerId peer) { return state() == State::Live && m_host->kick(peer); }

bool HostController::forceReleaseLock(session::PeerId holder) {
  return state() == State::Live && m_host->forceReleaseLock(holder);
}

spectral::LocatedFullVertices HostController::fullVertices(const spectral::DisplayVertexIds& displayed) const {
  const std::size_t n = m_model ? static_cast<std::size_t>(m_model->vertexCount()) : 0;
  spectral::LocatedFullVertices located;
  spectral::FullVertexIds& ids = located.ids;
  ids.reserve(displayed.size());
  for (const spectral::DisplayVertexId id : displayed) {
    if (id.index() < n) ids.emplace_back(id.value);
  }
  std::sort(ids.begin(), ids.end());
  ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
  located.points.resize(static_cast<Eigen::Index>(ids.size()), 3);
  for (std::size_t k = 0; k < ids.size(); ++k) {
    located.points.row(static_cast<Eigen::Index>(k)) = m_model->V.row(static_cast<Eigen::Index>(ids[k].index()));
  }
  return located;
}

spectral::DisplayVertexIds HostController::displayedVertices(const spectral::LocatedFullVertices& full) const {
  const std::size_t n = m_model ? static_cast<std::size_t>(m_model->vertexCount()) : 0;
  spectral::DisplayVertexIds ids = displayedIds(full.ids);
  std::erase_if(ids, [n](spectral::DisplayVertexId id) { return id.index() >= n; });
  return ids;
}

bool HostController::sendConstraints(const spectral::FullVertexIds& handle, const spectral::FullVertexIds& anchors) {
  // The same bound as a member's (constraint_work.h), so the host's own drag costs what a member's may.
  spectral::FullVertexIds held = anchors;
  if (m_model) session::thinAnchors(held, handle.size(), session::maxConstraintIds(m_model->rowCount()));
  return m_host->setConstraints(constraintSet(handle, held));
}

bool HostController::sendPose(const spectral::HandleTransform& pose) {
  // A pose out of range (non-finite, or a handle moved more than kMaxPoseTranslationDiagonals diagonals) is refused
  // here, so the editor keeps its last good pose; the deformer refuses it too (members' drags). O(#V) per drag.
  if (m_model == nullptr || !spectral::poseInRange(pose, spectral::maxPoseTranslation(m_model->V))) return false;
  return m_host->drag(std::span<const spectral::HandleTransform>(&pose, 1));
}

bool HostController::endStroke() { return m_host != nullptr && m_host->endStroke(); }

session::EditLog HostController::editLog() const {
  return state() == State::Live ? m_host->history().log() : session::EditLog{};
}

bool HostController::requestEdit(session::EditAction action) {
  if (state() != State::Live || dragging()) return false;
  return m_host->edit(action);
}

std::vector<session::EditStep> HostController::editSteps() const {
  if (state() != State::Live) return {};
  return {m_host->history().steps().begin(), m_host->history().steps().end()};
}

// ---------------------------------------------------------------------------------------------------- figures

quint16 HostController::tcpPort() const { return m_host != nullptr && state() == State::Live ? m_host->tcpPort() : 0; }

session::PeerId HostController::selfId() const { return m_host != nullptr ? session::kHostPeer : session::kNoPeer; }

Eigen::MatrixXd HostController::coefficients() const {
  return m_host != nullptr ? m_host->coefficients() : Eigen::MatrixXd();
}

std::vector<LevelChoice> HostController::levels() const {
  if (!m_model) return {};
  return {{0, tr("Full — %1 vertices").arg(QLocale().toString(m_model->vertexCount())), true}};
}

session::PeerList HostController::peers() const {
  return state() == State::Live ? m_host->peerList() : session::PeerList{};
}

std::optional<session::StatsReport> HostController::stats(session::PeerId peer) const {
  if (state() != State::Live) return std::nullopt;
  return m_host->stats(peer);
}

double HostController::sentKbps(session::PeerId peer) const {
  return m_host != nullptr ? m_host->channel().traffic(peer).payloadKbpsOut : 0.0;
}

QByteArray HostController::hostFingerprint() const { return m_host != nullptr ? m_host->fingerprint() : QByteArray(); }

session::HostEngineCounters HostController::counters() const {
  return m_host != nullptr ? m_host->counters() : session::HostEngineCounters{};
}

std::uint32_t HostController::currentFrame() const { return m_host != nullptr ? m_host->currentFrame() : 0; }

spectral::DeformationMode HostController::deformationMode() const {
  return m_host != nullptr ? m_host->options().deformer.mode : spectral::DeformationMode{};
}

}  // namespace sc::app
