// SessionHost: socket events into engine events. Accepting connections (admission by the engine), the
// HostPeerConnection signals (welcome, refusal, messages, errors, transfers, closing) and the level library's
// results.

#include "session/net/session_host.h"

#include "session/engine/session_clock.h"
#include "session/net/host_datagram_channel.h"
#include "session/net/host_peer_connection.h"
#include "session/net/level_library.h"
#include "session/net/tls_server.h"

#include <QtNetwork/QTcpSocket>

#include <algorithm>

namespace sc::session {

std::string admissionAddressKey(const QHostAddress& address) {
  bool isV4 = false;
  const quint32 v4 = address.toIPv4Address(&isV4);
  if (isV4) return QHostAddress(v4).toString().toStdString();
  if (address.protocol() != QAbstractSocket::IPv6Protocol) return address.toString().toStdString();
  Q_IPV6ADDR bytes = address.toIPv6Address();
  for (int i = 8; i < 16; ++i) bytes[i] = 0;  // the interface identifier: one host picks these freely
  return QStringLiteral("%1/64").arg(QHostAddress(bytes).toString()).toStdString();
}

void SessionHost::acceptConnections() {
  while (m_server->hasPendingConnections()) {
    QTcpSocket* socket = m_server->nextPendingConnection();
    const Micros now = sessionNow();
    const Admission admission = m_engine.onConnectionAttempt(admissionAddressKey(socket->peerAddress()), now);
    if (admission.evict != kNoPeer) {
      if (HostPeerConnection* evicted = connection(admission.evict)) evicted->abort();  // onClosed() follows
    }
    if (admission.peer == kNoPeer) {
      socket->abort();  // nothing read, nothing sent
      socket->deleteLater();
      continue;
    }
    HostHandshakeConfig config;
    config.secret = m_secret;
    config.sessionFull = [this] { return m_engine.sessionFull(); };
    config.nameTaken = [this](const QString& name) { return m_engine.nameTaken(name); };
    config.rowCount = static_cast<std::uint16_t>(m_model->rowCount());
    config.vertexCount = static_cast<std::uint32_t>(m_model->vertexCount());
    config.udpPort = m_channel->port();
    config.peerId = admission.peer;
    config.random = secureRandomBytes;
    config.channelBinding = fingerprint();
    config.timeout = m_engine.options().handshakeTimeout;
    auto* connection = new HostPeerConnection(socket, std::move(config), toMillis(now), this);
    connection->setSendBudget(m_engine.options().sendBudgetBytes);
    m_peers.emplace(admission.peer, connection);
    watch(connection);
  }
}

void SessionHost::watch(HostPeerConnection* connection) {
  const PeerId id = connection->peerId();
  connect(connection, &HostPeerConnection::welcomed, this, [this, connection, id] {
    const NegotiatedPeer& joined = *connection->peer();
    m_channel->addPeer(joined.peerId, joined.datagramKey, joined.pathToken);
    apply(m_engine.onWelcomed(id, joined.name, sessionNow()));
  });
  connect(connection, &HostPeerConnection::refused, this,
          [this, id](RefuseReason reason) { apply(m_engine.onRefused(id, reason, sessionNow())); });
  connect(connection, &HostPeerConnection::messageReceived, this,
          [this, connection, id](const ControlMessage& message) {
            if (connection->isClosing()) return;
            m_engine.onHeard(id, connection->lastHeard());
            apply(m_engine.onMessage(id, message, sessionNow()));
          });
  connect(connection, &HostPeerConnection::protocolError, this, [this, id](ControlError error) {
    apply(m_engine.onDecodeError(id, QString::fromLatin1(toString(error)), sessionNow()));
  });
  connect(connection, &HostPeerConnection::transferFinished, this,
          [this, id] { apply(m_engine.onTransferFinished(id, sessionNow())); });
  connect(connection, &HostPeerConnection::closed, this, [this, connection] { onClosed(connection); });
  connect(connection, &HostPeerConnection::tlsFailed, this,
          [this, id](const QString& why) { apply(m_engine.onTlsFailed(id, why)); });
  connect(connection, &HostPeerConnection::oversizeMessage, this, [this] { m_engine.onOversizeMessage(); });
}

void SessionHost::onClosed(HostPeerConnection* connection) {
  const PeerId id = connection->peerId();
  const auto it = m_peers.find(id);
  if (it == m_peers.end() || it->second != connection) return;
  m_peers.erase(it);
  connection->deleteLater();
  if (connection->isWelcomed()) m_channel->removePeer(id);
  apply(m_engine.onClosed(id, sessionNow()));
}

void SessionHost::onLevelReady(std::uint32_t target) {
  const LevelLibrary::Level* level = m_levels->find(target);
  if (level == nullptr) return;
  // One line per built level (shapecast-cli host prints it; scripts/large-mesh-e2e.sh reads it).
  emit logMessage(QStringLiteral("level built: %1 vertices, %2 faces, %3 bytes to send, in %4 s")
                      .arg(level->vertexCount)
                      .arg(level->faceCount)
                      .arg(level->payload.size())
                      .arg(level->buildSeconds, 0, 'f', 2));
  apply(m_engine.onLevelReady(target, LevelLibrary::figures(*level), sessionNow()));
}

void SessionHost::onLevelFailed(std::uint32_t target, const QString& reason) {
  apply(m_engine.onLevelFailed(target, reason, sessionNow()));
}

}  // namespace sc::session
