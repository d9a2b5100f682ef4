#include "session/net/host_peer_connection.h"

#include "session/engine/session_clock.h"

#include <QtCore/QTimer>
#include <QtNetwork/QSslSocket>

#include <algorithm>

namespace sc::session {
namespace {

constexpr int kCloseGraceMs = 2000;  ///< a closing socket whose peer does not read is aborted after this

Millis nowMillis() { return std::chrono::duration_cast<Millis>(sessionNow()); }

bool isTlsError(QAbstractSocket::SocketError error) {
  return error == QAbstractSocket::SslHandshakeFailedError || error == QAbstractSocket::SslInternalError ||
         error == QAbstractSocket::SslInvalidUserDataError;
}

}  // namespace

HostPeerConnection::HostPeerConnection(QTcpSocket* socket, HostHandshakeConfig config, Millis now, QObject* parent)
    : QObject(parent),
      m_socket(socket),
      m_peerId(config.peerId),
      m_handshake(std::move(config), now),
      m_lastHeard(now),
      m_lastDrained(sessionNow()) {
  socket->setParent(this);
  socket->setSocketOption(QAbstractSocket::LowDelayOption, 1);
  connect(socket, &QTcpSocket::readyRead, this, &HostPeerConnection::readAvailable);
  if (auto* tls = qobject_cast<QSslSocket*>(socket)) {
    // TLS moves written bytes to the encrypted buffer at once (bytesWritten then says nothing about the peer
    // reading): only the kernel taking encrypted bytes counts as draining; pump again then too.
    connect(tls, &QSslSocket::bytesWritten, this, &HostPeerConnection::pumpTransfer);
    connect(tls, &QSslSocket::encryptedBytesWritten, this, &HostPeerConnection::onDrained);
  } else {
    connect(socket, &QTcpSocket::bytesWritten, this, &HostPeerConnection::onDrained);
  }
  connect(socket, &QTcpSocket::disconnected, this, &HostPeerConnection::onDisconnected);
  connect(socket, &QTcpSocket::errorOccurred, this, [this](QAbstractSocket::SocketError error) {
    if (m_socket && isTlsError(error)) {
      emit tlsFailed(m_socket->errorString());
      abort();
      return;
    }
    if (m_socket && m_socket->state() == QAbstractSocket::UnconnectedState) onDisconnected();
  });
}

HostPeerConnection::~HostPeerConnection() = default;

QHostAddress HostPeerConnection::peerAddress() const { return m_socket ? m_socket->peerAddress() : QHostAddress(); }

void HostPeerConnection::send(const ControlMessage& message) { sendEncoded(encodeControlMessage(message)); }

void HostPeerConnection::sendEncoded(const QByteArray& frame) {
  if (frame.isEmpty() || m_closing || m_overBudget || !m_socket ||
      m_socket->state() != QAbstractSocket::ConnectedState) {
    return;
  }
  const qint64 queued = queuedBytes();
  if (queued == 0) m_lastDrained = sessionNow();  // nothing was waiting: the stall clock starts now
  if (queued + frame.size() > m_sendBudget) {
    m_overBudget = true;  // the stream is now incomplete: the host drops this peer (HostEngine::onSendQueue)
    return;
  }
  m_socket->write(frame);
  m_peakQueued = std::max(m_peakQueued, queuedBytes());
}

SendQueueReport HostPeerConnection::sendQueue() const {
  SendQueueReport report;
  report.queuedBytes = queuedBytes();
  report.peakBytes = m_peakQueued;
  report.lastDrained = report.queuedBytes == 0 ? sessionNow() : m_lastDrained;
  report.overBudget = m_overBudget;
  return report;
}

void HostPeerConnection::onDrained() {
  m_lastDrained = sessionNow();
  pumpTransfer();
}

void HostPeerConnection::tickHandshake(Millis now) {
  if (m_closing || isWelcomed()) return;
  handleHandshakeResult(m_handshake.tick(now));
}

void HostPeerConnection::startTransfer(std::unique_ptr<ModelSender> sender) {
  if (m_closing) return;
  m_transfer = std::move(sender);
  send(m_transfer->begin());
  pumpTransfer();
}

void HostPeerConnection::close() {
  if (m_closing || !m_socket) return;
  m_closing = true;
  m_transfer.reset();
  m_socket->disconnectFromHost();  // writes what is queued first
  if (m_socket && m_socket->state() != QAbstractSocket::UnconnectedState) {
    QTimer::singleShot(kCloseGraceMs, this, [this] { abort(); });
  }
}

void HostPeerConnection::abort() {
  m_closing = true;
  m_transfer.reset();
  if (m_socket) m_socket->abort();
  onDisconnected();
}

void HostPeerConnection::readAvailable() {
  if (!m_socket) return;
  const QByteArray bytes = m_socket->readAll();
  if (bytes.isEmpty() || m_closing) return;
  m_lastHeard = nowMillis();
  m_reader.append(bytes);
  while (!m_closing) {
    std::optional<ControlDecodeResult> result = m_reader.next();
    if (!result) break;
    if (result->error == ControlError::Oversize) emit oversizeMessage();
    if (!isWelcomed()) {
      handleHandshakeResult(result->error == ControlError::None ? m_handshake.handleMessage(result->message)
                                                                : m_handshake.handleDecodeError(result->error));
      continue;
    }
    if (result->error != ControlError::None) {
      emit protocolError(result->error);
      return;  // the host closes the connection; nothing more is read
    }
    emit messageReceived(result->message);
  }
}

void HostPeerConnection::handleHandshakeResult(const HandshakeOutput& out) {
  for (const ControlMessage& message : out.send) send(message);
  if (m_handshake.state() == HostHandshake::State::Refused) {
    const RefuseReason reason = m_handshake.refusal() ? m_handshake.refusal()->reason : RefuseReason::ProtocolError;
    emit refused(reason);
    close();
  } else if (out.close) {
    close();
  } else if (isWelcomed()) {
    emit welcomed();
  }
}

void HostPeerConnection::pumpTransfer() {
  // A socket no longer connected writes nothing (nothing stays queued): without the state check a dead peer's
  // whole transfer would be "sent" into the void at once and counted as finished.
  // Below half the send budget too, so that a transfer alone never brings an honest peer near the budget.
  const qint64 highWater = std::min(kTransferHighWater, m_sendBudget / 2);
  while (m_transfer && !m_closing && m_socket && queuedBytes() < highWater) {
    std::optional<ModelChunk> chunk = m_transfer->nextChunk();
    if (chunk) send(*chunk);
    if (m_transfer->finished()) {
      const std::uint32_t id = m_transfer->begin().transferId;
      m_transfer.reset();
      emit transferFinished(id);
      return;
    }
  }
}

qint64 HostPeerConnection::queuedBytes() const {
  if (!m_socket) return 0;
  const auto* tls = qobject_cast<const QSslSocket*>(m_socket.data());
  return m_socket->bytesToWrite() + (tls ? tls->encryptedBytesToWrite() : 0);
}

void HostPeerConnection::onDisconnected() {
  if (m_closedEmitted) return;
  m_closedEmitted = true;
  m_closing = true;
  m_transfer.reset();
  emit closed();
}

}  // namespace sc::session
