// SessionHost: construction, start/shutdown, queries, broadcasts and the periodic timers. Peer connections and
// model transfers are in session_host_peers.cpp, the lock, constraints and drags in session_host_lock.cpp, frame
// production in session_host_frames.cpp.

#include "session/net/session_host.h"

#include "session/net/host_datagram_channel.h"
#include "session/net/host_peer_connection.h"
#include "session/net/level_library.h"
#include "session/engine/session_clock.h"
#include "session/net/session_host_peer.h"
#include "session/net/tls_server.h"

#include <QtCore/QPointer>
#include <QtCore/QTimer>

#include <algorithm>

namespace sc::session {
namespace {

constexpr int kHousekeepingMs = 100;  ///< handshake timeouts, lock lease, own renew, idle refresh
constexpr int kHeartbeatMs = 1000;

}  // namespace

SessionHost::SessionHost(std::shared_ptr<const HostModel> model, SessionHostOptions options, QObject* parent)
    : QObject(parent), m_model(std::move(model)), m_options(std::move(options)) {
  m_server = new TlsServer(this);
  m_channel = new HostDatagramChannel(m_options.codec, this);
  m_levels = new LevelLibrary(m_model, this);
  m_housekeeping = new QTimer(this);
  m_heartbeat = new QTimer(this);
  m_coalesce = new QTimer(this);
  m_coalesce->setSingleShot(true);
  m_coalesce->setTimerType(Qt::PreciseTimer);
  m_still = new QTimer(this);
  m_still->setSingleShot(true);
  m_still->setTimerType(Qt::PreciseTimer);
  m_deformer =
      std::make_unique<spectral::SpectralDeformer>(m_model->basis, m_model->operators, m_model->V, m_options.deformer);
  m_Z = Eigen::MatrixXd::Zero(m_model->rowCount(), 3);

  connect(m_server, &QTcpServer::newConnection, this, &SessionHost::acceptConnections);
  connect(m_levels, &LevelLibrary::levelReady, this, &SessionHost::onLevelReady);
  connect(m_levels, &LevelLibrary::levelFailed, this, &SessionHost::onLevelFailed);
  connect(m_housekeeping, &QTimer::timeout, this, &SessionHost::housekeeping);
  connect(m_heartbeat, &QTimer::timeout, this, &SessionHost::heartbeat);
  connect(m_coalesce, &QTimer::timeout, this, &SessionHost::produceFrame);
  connect(m_still, &QTimer::timeout, this, &SessionHost::produceStillFrame);
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
  m_options.maxPendingHandshakes = std::max(m_options.maxPendingHandshakes, 1);
  m_options.maxPendingPerAddress = std::max(m_options.maxPendingPerAddress, 1);
  if (!resolveIdentity(error)) return false;
  m_server->setSslConfiguration(hostTlsConfiguration(m_identity->certificate, m_identity->privateKey));
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
  emit logMessage(QStringLiteral("certificate fingerprint (SHA-256): %1").arg(formatFingerprint(fingerprint())));
  return true;
}

bool SessionHost::resolveIdentity(QString* error) {
  m_identity = m_options.identity;
  if (m_identity) {
    if (!m_identity->certificate.isNull() && !m_identity->privateKey.isNull()) return true;
    if (error) *error = QStringLiteral("the TLS identity has no certificate or no key");
    return false;
  }
  QString why;
  const QString directory = defaultTlsIdentityDirectory();
  if (std::optional<TlsIdentity> stored = loadOrCreateTlsIdentity(directory, &why)) {
    m_identity = std::make_shared<const TlsIdentity>(std::move(*stored));
    return true;
  }
  emit logMessage(QStringLiteral("cannot use the stored TLS identity (%1): using a new one for this run").arg(why));
  std::optional<TlsIdentity> fresh = generateTlsIdentity(QStringLiteral("ShapeCast host"), &why);
  if (!fresh) {
    if (error) *error = QStringLiteral("no TLS identity: %1").arg(why);
    return false;
  }
  m_identity = std::make_shared<const TlsIdentity>(std::move(*fresh));
  return true;
}

void SessionHost::shutdown() {
  if (m_shutDown) return;
  m_shutDown = true;
  m_housekeeping->stop();
  m_heartbeat->stop();
  m_coalesce->stop();
  m_still->stop();
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
