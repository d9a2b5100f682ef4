// SessionHost: peer connection management (accepting, handshake results, incoming messages, closing) and the
// model transfers of LevelLibrary levels to peers.

#include "session/net/session_host.h"

#include "session/net/host_datagram_channel.h"
#include "session/net/host_peer_connection.h"
#include "session/net/level_library.h"
#include "session/wire/model_transfer.h"
#include "session/engine/session_clock.h"
#include "session/net/session_host_peer.h"

#include "session/net/tls_server.h"

#include <QtNetwork/QTcpSocket>

#include <algorithm>

namespace sc::session {
namespace {

QString describe(MessageType type) {
  return QStringLiteral("0x%1").arg(static_cast<int>(type), 2, 16, QLatin1Char('0'));
}

}  // namespace

// --- connections

PeerId SessionHost::allocatePeerId() {
  for (int attempt = 0; attempt < 0xffff; ++attempt) {
    const PeerId id = m_nextPeerId;
    m_nextPeerId = id >= 0xffff ? kHostPeer + 1 : id + 1;
    if (!m_peers.contains(id)) return id;
  }
  return kNoPeer;
}

bool SessionHost::admits(const QHostAddress& address) const {
  int pending = 0;
  int fromAddress = 0;
  for (const auto& [id, peer] : m_peers) {
    const HostPeerConnection* c = peer->connection;
    if (c->isWelcomed() || c->isClosing()) continue;
    ++pending;
    if (c->peerAddress().isEqual(address, QHostAddress::TolerantConversion)) ++fromAddress;
  }
  return pending < m_options.maxPendingHandshakes && fromAddress < m_options.maxPendingPerAddress;
}

void SessionHost::acceptConnections() {
  while (m_server->hasPendingConnections()) {
    QTcpSocket* socket = m_server->nextPendingConnection();
    const bool admitted = !m_shutDown && admits(socket->peerAddress());
    const PeerId id = admitted ? allocatePeerId() : kNoPeer;
    if (id == kNoPeer) {
      if (!m_shutDown) ++m_counters.connectionsOverLimit;
      socket->abort();  // nothing read, nothing sent
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
    config.channelBinding = fingerprint();
    config.timeout = std::max(m_options.handshakeTimeout, Millis{1});
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
    connect(connection, &HostPeerConnection::tlsFailed, this, [this, connection](const QString& why) {
      ++m_counters.tlsFailures;
      emit logMessage(
          QStringLiteral("TLS handshake with %1 failed: %2").arg(connection->peerAddress().toString(), why));
    });
    connect(connection, &HostPeerConnection::oversizeMessage, this, [this] { ++m_counters.oversizeMessages; });
  }
}

void SessionHost::onWelcomed(HostPeerConnection* connection) {
  const NegotiatedPeer& joined = *connection->peer();
  m_channel->addPeer(joined.peerId, joined.datagramKey, joined.pathToken);
  broadcastPeerList();
  // The exact level figures built so far; the rest of the ladder is built in the background and each new level
  // re-sends the list to everybody (onLevelReady).
  connection->send(m_levels->levelList());
  m_levels->prefetchAll();
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
  broadcast(m_levels->levelList());
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

}  // namespace sc::session
