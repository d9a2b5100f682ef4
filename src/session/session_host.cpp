#include "session/session_host.h"

#include "session/handle_transforms.h"
#include "session/host_datagram_channel.h"
#include "session/host_peer_connection.h"
#include "session/level_library.h"
#include "session/model_transfer.h"
#include "session/session_clock.h"

#include <QtCore/QPointer>
#include <QtCore/QTimer>
#include <QtNetwork/QTcpServer>
#include <QtNetwork/QTcpSocket>

#include <algorithm>

namespace sc::session {
namespace {

constexpr int kHousekeepingMs = 100;  ///< handshake timeouts, lock lease, own renew, idle refresh
constexpr int kHeartbeatMs = 1000;

QString describe(MessageType type) {
  return QStringLiteral("0x%1").arg(static_cast<int>(type), 2, 16, QLatin1Char('0'));
}

}  // namespace

struct SessionHost::Peer {
  HostPeerConnection* connection = nullptr;  ///< child of the host, deleted (later) when closed
  std::optional<std::uint32_t> waitingFor;   ///< ladder target whose build this peer's transfer waits for
  std::uint32_t transferTarget = 0;          ///< ladder target of the transfer in flight
  std::uint32_t transferVertexCount = 0;     ///< level of the transfer in flight
  std::uint32_t loadedVertexCount = 0;       ///< level of the last completed transfer (0: none yet)
  std::optional<StatsReport> stats;
};

SessionHost::SessionHost(std::shared_ptr<const HostModel> model, SessionHostOptions options, QObject* parent)
    : QObject(parent), m_model(std::move(model)), m_options(std::move(options)) {
  m_server = new QTcpServer(this);
  m_channel = new HostDatagramChannel(m_options.codec, this);
  m_levels = new LevelLibrary(m_model, this);
  m_housekeeping = new QTimer(this);
  m_heartbeat = new QTimer(this);
  m_coalesce = new QTimer(this);
  m_coalesce->setSingleShot(true);
  m_coalesce->setTimerType(Qt::PreciseTimer);
  m_deformer =
      std::make_unique<spectral::SpectralDeformer>(m_model->basis, m_model->operators, m_model->V, m_options.deformer);
  m_Z = Eigen::MatrixXd::Zero(m_model->rowCount(), 3);

  connect(m_server, &QTcpServer::newConnection, this, &SessionHost::acceptConnections);
  connect(m_levels, &LevelLibrary::levelReady, this, &SessionHost::onLevelReady);
  connect(m_levels, &LevelLibrary::levelFailed, this, &SessionHost::onLevelFailed);
  connect(m_housekeeping, &QTimer::timeout, this, &SessionHost::housekeeping);
  connect(m_heartbeat, &QTimer::timeout, this, &SessionHost::heartbeat);
  connect(m_coalesce, &QTimer::timeout, this, &SessionHost::produceFrame);
}

SessionHost::~SessionHost() {
  for (auto& [id, peer] : m_peers) disconnect(peer->connection, nullptr, this, nullptr);
}

Millis SessionHost::now() const { return std::chrono::duration_cast<Millis>(sessionNow()); }

bool SessionHost::start(QString* error) {
  const auto fail = [error](const QString& why) {
    if (error) *error = why;
    return false;
  };
  if (m_started) return fail(QStringLiteral("the host is already started"));
  if (!isAcceptableDisplayName(m_options.hostName) || m_options.hostName.toUtf8().size() > kMaxNameBytes) {
    return fail(QStringLiteral("host name \"%1\" is not a valid display name").arg(m_options.hostName));
  }
  if (m_model->rowCount() < 1 || m_model->rowCount() > kMaxRows || m_model->vertexCount() < 3) {
    return fail(QStringLiteral("the model needs 1..%1 basis functions and at least 3 vertices").arg(kMaxRows));
  }
  m_options.maxPeers = std::clamp(m_options.maxPeers, 1, kMaxPeers - 1);
  if (m_options.password) {
    const std::uint32_t iterations = std::clamp<std::uint32_t>(m_options.pbkdf2Iterations, 1, kMaxPbkdf2Iterations);
    m_secret = makeSessionSecret(*m_options.password, iterations, secureRandomBytes);
  }
  QString channelError;
  if (!m_channel->bind(m_options.address, m_options.udpPort, &channelError)) {
    return fail(QStringLiteral("UDP bind failed: %1").arg(channelError));
  }
  if (!m_server->listen(m_options.address, m_options.tcpPort)) {
    return fail(QStringLiteral("TCP listen failed: %1").arg(m_server->errorString()));
  }
  m_started = true;
  m_lastFrameAt = sessionNow();
  m_housekeeping->start(kHousekeepingMs);
  m_heartbeat->start(kHeartbeatMs);
  emit logMessage(QStringLiteral("hosting on TCP %1, UDP %2").arg(tcpPort()).arg(udpPort()));
  return true;
}

void SessionHost::shutdown() {
  if (m_shutDown) return;
  m_shutDown = true;
  m_housekeeping->stop();
  m_heartbeat->stop();
  m_coalesce->stop();
  m_server->close();
  std::vector<QPointer<HostPeerConnection>> connections;
  for (auto& [id, peer] : m_peers) connections.emplace_back(peer->connection);
  for (const QPointer<HostPeerConnection>& connection : connections) {
    if (!connection) continue;
    if (connection->isWelcomed()) {
      connection->send(Leave{});
    } else {
      connection->send(Refused{RefuseReason::ShuttingDown, kProtocolVersion, QStringLiteral("the host is closing")});
    }
    connection->close();
  }
  emit logMessage(QStringLiteral("session closed"));
}

quint16 SessionHost::tcpPort() const { return m_server->serverPort(); }
quint16 SessionHost::udpPort() const { return m_channel->port(); }
PeerId SessionHost::lockHolder() const { return m_arbiter.holder(); }
LockEpoch SessionHost::lockEpoch() const { return m_arbiter.epoch(); }
const std::deque<PeerId>& SessionHost::lockQueue() const { return m_arbiter.queue(); }

std::optional<StatsReport> SessionHost::stats(PeerId peer) const {
  const auto it = m_peers.find(peer);
  return it == m_peers.end() ? std::nullopt : it->second->stats;
}

PeerList SessionHost::peerList() const {
  PeerList list;
  list.peers.push_back({kHostPeer, static_cast<std::uint32_t>(m_model->vertexCount()), m_options.hostName});
  for (const auto& [id, peer] : m_peers) {
    if (!peer->connection->isWelcomed() || peer->connection->isClosing() || !peer->connection->peer()) continue;
    list.peers.push_back({id, peer->loadedVertexCount, peer->connection->peer()->name});
  }
  return list;
}

// --- connections

PeerId SessionHost::allocatePeerId() {
  for (int attempt = 0; attempt < 0xffff; ++attempt) {
    const PeerId id = m_nextPeerId;
    m_nextPeerId = id >= 0xffff ? kHostPeer + 1 : id + 1;
    if (!m_peers.contains(id)) return id;
  }
  return kNoPeer;
}

void SessionHost::acceptConnections() {
  while (m_server->hasPendingConnections()) {
    QTcpSocket* socket = m_server->nextPendingConnection();
    const PeerId id = m_shutDown ? kNoPeer : allocatePeerId();
    if (id == kNoPeer) {
      socket->abort();
      socket->deleteLater();
      continue;
    }
    HostHandshakeConfig config;
    config.secret = m_secret;
    config.sessionFull = static_cast<int>(m_peers.size()) >= m_options.maxPeers;
    config.nameTaken = [this](const QString& name) {
      if (name == m_options.hostName) return true;
      return std::any_of(m_peers.begin(), m_peers.end(), [&name](const auto& entry) {
        const HostPeerConnection* c = entry.second->connection;
        return c->isWelcomed() && c->peer() && c->peer()->name == name;
      });
    };
    config.rowCount = static_cast<std::uint16_t>(m_model->rowCount());
    config.vertexCount = static_cast<std::uint32_t>(m_model->vertexCount());
    config.udpPort = m_channel->port();
    config.peerId = id;
    config.random = secureRandomBytes;
    auto* connection = new HostPeerConnection(socket, std::move(config), now(), this);
    auto peer = std::make_unique<Peer>();
    peer->connection = connection;
    m_peers.emplace(id, std::move(peer));
    connect(connection, &HostPeerConnection::welcomed, this, [this, connection] { onWelcomed(connection); });
    connect(connection, &HostPeerConnection::refused, this, [this](RefuseReason reason) {
      const auto index = static_cast<std::size_t>(reason);
      if (index < m_counters.refusals.size()) ++m_counters.refusals[index];
    });
    connect(connection, &HostPeerConnection::messageReceived, this,
            [this, connection](const ControlMessage& message) { onMessage(connection, message); });
    connect(connection, &HostPeerConnection::protocolError, this, [this, connection](ControlError error) {
      protocolFailure(connection, QString::fromLatin1(toString(error)));
    });
    connect(connection, &HostPeerConnection::transferFinished, this,
            [this, connection] { onTransferFinished(connection); });
    connect(connection, &HostPeerConnection::closed, this, [this, connection] { onClosed(connection); });
  }
}

void SessionHost::onWelcomed(HostPeerConnection* connection) {
  const NegotiatedPeer& joined = *connection->peer();
  m_channel->addPeer(joined.peerId, joined.datagramKey, joined.pathToken);
  broadcastPeerList();
  if (m_arbiter.holder() != kNoPeer) {
    connection->send(LockNotice{LockNoticeKind::Granted, m_arbiter.holder(), m_arbiter.epoch(), 0, {}});
  }
  emit logMessage(QStringLiteral("%1 joined as peer %2 from %3")
                      .arg(joined.name)
                      .arg(joined.peerId)
                      .arg(connection->peerAddress().toString()));
  emit peersChanged();
}

void SessionHost::onClosed(HostPeerConnection* connection) {
  const PeerId id = connection->peerId();
  const auto it = m_peers.find(id);
  if (it == m_peers.end() || it->second->connection != connection) return;
  const bool wasMember = connection->isWelcomed();
  m_peers.erase(it);
  connection->deleteLater();
  if (!wasMember) return;
  m_channel->removePeer(id);
  dispatchLock(m_arbiter.peerDisconnected(id, now()));
  broadcastPeerList();
  emit logMessage(QStringLiteral("peer %1 left").arg(id));
  emit peersChanged();
}

void SessionHost::protocolFailure(HostPeerConnection* connection, const QString& why) {
  ++m_counters.protocolErrors;
  emit logMessage(
      QStringLiteral("protocol error from peer %1 (%2): connection closed").arg(connection->peerId()).arg(why));
  connection->close();
}

void SessionHost::onMessage(HostPeerConnection* connection, const ControlMessage& message) {
  const PeerId id = connection->peerId();
  const auto it = m_peers.find(id);
  if (it == m_peers.end() || connection->isClosing()) return;
  Peer& peer = *it->second;
  switch (messageType(message)) {
    case MessageType::ResolutionRequest:
      handleResolutionRequest(peer, std::get<ResolutionRequest>(message));
      return;
    case MessageType::LockRequest:
      dispatchLock(m_arbiter.handleMessage(id, std::get<LockMessage>(message), now()));
      return;
    case MessageType::Constraints:
      handleConstraints(id, std::get<Constraints>(message));
      return;
    case MessageType::Drag:
      handleDrag(id, std::get<Drag>(message), sessionNow());
      return;
    case MessageType::StatsReport:
      peer.stats = std::get<StatsReport>(message);
      emit statsReported(id, *peer.stats);
      return;
    case MessageType::Heartbeat:
      return;  // the connection already noted the bytes
    case MessageType::Leave:
      connection->abort();  // onClosed() cleans up; `peer` is gone after this
      return;
    default:
      protocolFailure(connection, QStringLiteral("unexpected message %1").arg(describe(messageType(message))));
      return;
  }
}

// --- model transfer

void SessionHost::handleResolutionRequest(Peer& peer, const ResolutionRequest& request) {
  const std::uint32_t target = m_levels->pick(request.vertexCount);
  if (peer.connection->isTransferring() && peer.transferTarget == target) return;  // already on its way
  if (m_levels->find(target)) {
    startTransfer(peer, target);
    return;
  }
  peer.waitingFor = target;
  m_levels->request(target);
}

void SessionHost::startTransfer(Peer& peer, std::uint32_t target) {
  const LevelLibrary::Level* level = m_levels->find(target);
  if (!level) return;
  peer.waitingFor.reset();
  if (++m_transferId == 0) m_transferId = 1;
  peer.transferTarget = target;
  peer.transferVertexCount = level->vertexCount;
  peer.connection->startTransfer(
      std::make_unique<ModelSender>(m_transferId, level->kind, level->vertexCount, level->payload, level->sha256));
}

void SessionHost::onLevelReady(std::uint32_t target) {
  std::vector<PeerId> waiting;
  for (const auto& [id, peer] : m_peers) {
    if (peer->waitingFor == target) waiting.push_back(id);
  }
  for (const PeerId id : waiting) {
    const auto it = m_peers.find(id);
    if (it != m_peers.end()) startTransfer(*it->second, target);
  }
}

void SessionHost::onLevelFailed(std::uint32_t target, const QString& reason) {
  emit logMessage(QStringLiteral("level %1 unavailable: %2").arg(target).arg(reason));
  const std::uint32_t full = m_levels->fullTarget();
  for (auto& [id, peer] : m_peers) {
    if (peer->waitingFor != target) continue;
    if (target == full) {
      peer->waitingFor.reset();  // nothing left to send
    } else {
      peer->waitingFor = full;  // fall back to the full model
    }
  }
  if (target != full) {
    if (m_levels->find(full)) {
      onLevelReady(full);
    } else {
      m_levels->request(full);
    }
  }
}

void SessionHost::onTransferFinished(HostPeerConnection* connection) {
  const auto it = m_peers.find(connection->peerId());
  if (it == m_peers.end()) return;
  it->second->loadedVertexCount = it->second->transferVertexCount;
  ++m_counters.transfersCompleted;
  sendKeyframe(*connection);
  broadcastPeerList();
  emit peersChanged();
}

// --- lock, constraints, drags

void SessionHost::dispatchLock(const LockEvents& events) {
  for (const LockEvent& event : events) {
    const bool toHost = event.audience == LockAudience::AllPeers || event.recipient == kHostPeer;
    const QByteArray frame = encodeControlMessage(event.notice);
    for (const auto& [id, peer] : m_peers) {
      if (!peer->connection->isWelcomed()) continue;
      if (event.audience == LockAudience::AllPeers || event.recipient == id) peer->connection->sendEncoded(frame);
    }
    if (toHost) {
      if (const std::optional<LockMessage> reply = m_localLock.apply(event.notice, now())) {
        dispatchLock(m_arbiter.handleMessage(kHostPeer, *reply, now()));
      }
    }
  }
  if (!events.empty()) emit lockChanged();
}

bool SessionHost::requestLock() {
  const std::optional<LockMessage> message = m_localLock.request(now());
  if (message) dispatchLock(m_arbiter.handleMessage(kHostPeer, *message, now()));
  return message.has_value();
}

bool SessionHost::releaseLock() {
  const std::optional<LockMessage> message = m_localLock.release(now());
  if (message) dispatchLock(m_arbiter.handleMessage(kHostPeer, *message, now()));
  return message.has_value();
}

bool SessionHost::setConstraints(const spectral::ConstraintSet& constraints) {
  return applyConstraints(kHostPeer, m_localLock.heldEpoch(), constraints);
}

bool SessionHost::drag(std::span<const spectral::HandleTransform> poses) {
  return acceptPose(kHostPeer, m_localLock.heldEpoch(), {poses.begin(), poses.end()}, sessionNow());
}

void SessionHost::handleConstraints(PeerId peer, const Constraints& constraints) {
  const auto n = static_cast<std::uint32_t>(m_model->vertexCount());
  const auto valid = [n](std::uint32_t id) { return id < n; };
  spectral::ConstraintSet set;
  bool idsValid = std::all_of(constraints.anchors.begin(), constraints.anchors.end(), valid);
  for (const std::vector<std::uint32_t>& group : constraints.groups) {
    idsValid = idsValid && std::all_of(group.begin(), group.end(), valid);
    if (!idsValid) break;
    set.handles.push_back({std::vector<int>(group.begin(), group.end())});
  }
  if (!idsValid) {
    ++m_counters.constraintsRejected;
    return;
  }
  set.anchors.assign(constraints.anchors.begin(), constraints.anchors.end());
  applyConstraints(peer, constraints.epoch, set);
}

bool SessionHost::applyConstraints(PeerId peer, LockEpoch epoch, const spectral::ConstraintSet& set) {
  if (m_arbiter.acceptDrag(peer, epoch, now()) != DragVerdict::Accepted || !m_deformer->setConstraints(set)) {
    ++m_counters.constraintsRejected;
    return false;
  }
  ++m_counters.constraintsAccepted;
  m_pendingArrival.reset();  // a pose for the previous groups means nothing now
  return true;
}

void SessionHost::handleDrag(PeerId peer, const Drag& drag, Micros arrivedAt) {
  acceptPose(peer, drag.epoch, fromWire(drag.handles, m_deformer->constraints().handles.size()), arrivedAt);
}

bool SessionHost::acceptPose(PeerId peer, LockEpoch epoch, std::vector<spectral::HandleTransform> poses,
                             Micros arrivedAt) {
  switch (m_arbiter.acceptDrag(peer, epoch, now())) {
    case DragVerdict::NotHolder:
      ++m_counters.dragsNotHolder;
      return false;
    case DragVerdict::StaleEpoch:
      ++m_counters.dragsStale;
      return false;
    case DragVerdict::Accepted:
      break;
  }
  ++m_counters.dragsAccepted;
  m_pendingPoses = std::move(poses);
  m_pendingArrival = arrivedAt;
  if (m_coalesce->isActive()) return true;  // the pending timer sends the latest pose
  const Micros since = sessionNow() - m_lastFrameAt;
  const Micros spacing = std::chrono::duration_cast<Micros>(m_options.coalesce);
  if (since >= spacing) {
    produceFrame();
  } else {
    const auto wait = std::chrono::ceil<Millis>(spacing - since);
    m_coalesce->start(std::max<int>(1, static_cast<int>(wait.count())));
  }
  return true;
}

// --- frames

void SessionHost::produceFrame() {
  if (m_shutDown) return;
  const Micros t = sessionNow();
  Micros stamp = t;
  if (m_pendingArrival) {
    m_Z = m_deformer->solve(m_pendingPoses);
    stamp = *m_pendingArrival;
    m_pendingArrival.reset();
  }
  ++m_frame;
  m_channel->sendFrame(m_frame, m_Z, stamp);
  m_lastFrameAt = t;
  ++m_counters.framesSent;
  if (m_options.referenceEvery > 0 && ++m_framesSinceKeyframe >= m_options.referenceEvery) {
    m_framesSinceKeyframe = 0;
    for (const auto& [id, peer] : m_peers) {
      if (peer->loadedVertexCount > 0 && !peer->connection->isClosing()) sendKeyframe(*peer->connection);
    }
  }
  emit frameSent(m_frame);
}

void SessionHost::sendKeyframe(HostPeerConnection& connection) {
  Keyframe keyframe;
  keyframe.frame = m_frame;
  keyframe.z.resize(static_cast<std::size_t>(m_Z.rows()) * 3);
  for (Eigen::Index r = 0; r < m_Z.rows(); ++r) {
    for (Eigen::Index c = 0; c < 3; ++c) keyframe.z[static_cast<std::size_t>(3 * r + c)] = m_Z(r, c);
  }
  connection.send(keyframe);
  ++m_counters.keyframesSent;
}

// --- timers and broadcasts

void SessionHost::broadcast(const ControlMessage& message) {
  const QByteArray frame = encodeControlMessage(message);
  if (frame.isEmpty()) return;
  for (const auto& [id, peer] : m_peers) {
    if (peer->connection->isWelcomed()) peer->connection->sendEncoded(frame);
  }
}

void SessionHost::broadcastPeerList() { broadcast(peerList()); }

void SessionHost::housekeeping() {
  const Millis t = now();
  std::vector<QPointer<HostPeerConnection>> pending;
  for (const auto& [id, peer] : m_peers) {
    if (!peer->connection->isWelcomed()) pending.emplace_back(peer->connection);
  }
  for (const QPointer<HostPeerConnection>& connection : pending) {
    if (connection) connection->tickHandshake(t);
  }
  dispatchLock(m_arbiter.tick(t));
  if (const std::optional<LockMessage> renew = m_localLock.pollRenew(t)) {
    dispatchLock(m_arbiter.handleMessage(kHostPeer, *renew, t));
  }
  const bool idle = sessionNow() - m_lastFrameAt >= std::chrono::duration_cast<Micros>(m_options.idleRefresh);
  if (idle && !m_coalesce->isActive()) produceFrame();
}

void SessionHost::heartbeat() {
  const Millis t = now();
  const Heartbeat beat{m_heartbeatSequence++};
  std::vector<QPointer<HostPeerConnection>> silent;
  for (const auto& [id, peer] : m_peers) {
    HostPeerConnection* connection = peer->connection;
    if (!connection->isWelcomed() || connection->isClosing()) continue;
    if (t - connection->lastHeard() > m_options.peerTimeout) {
      silent.emplace_back(connection);
    } else {
      connection->send(beat);
    }
  }
  for (const QPointer<HostPeerConnection>& connection : silent) {
    if (!connection) continue;
    ++m_counters.silentPeersDropped;
    emit logMessage(QStringLiteral("peer %1 silent for too long: dropped").arg(connection->peerId()));
    connection->abort();
  }
}

}  // namespace sc::session
