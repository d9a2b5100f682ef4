#pragma once
// One client's TCP control connection on the host: the socket adapter around a ControlFrameReader and a
// HostHandshake (style.md item 11: the state machines have no sockets; this class feeds them). SessionHost owns
// one per accepted socket and handles what it emits.
//
// Contracts
//   - Until the handshake ends, every decoded message (or decode error) goes to the HostHandshake; what it returns
//     is sent, and a refusal is flushed and the connection closed (refused() first). After Welcome (welcomed()),
//     each decoded message is emitted as messageReceived(); a decode error is emitted as protocolError() and the
//     connection stops reading (the host's rule is to close it). Network input never asserts.
//   - Model transfers: startTransfer() sends the ModelBegin, then chunks only while fewer than kTransferHighWater
//     (and half the send budget) bytes are queued in the socket (TLS: plaintext plus encrypted bytes), continuing on
//     bytesWritten (TLS: also encryptedBytesWritten), so other messages are never stuck behind a whole model. A new
//     transfer replaces an unfinished one (the receiver abandons it on the new ModelBegin).
//   - Send budget: a write that would raise the queue (queuedBytes()) above setSendBudget()'s value is not made and
//     the connection is marked over budget (sendQueue().overBudget; its stream is then incomplete, the host drops
//     it): the host never buffers more than the budget for one peer. sendQueue() measures the queue, its peak and
//     when the kernel last took bytes (or the queue was seen empty); the engine decides (HostEngine::onSendQueue).
//   - closed() is emitted exactly once, when the socket is gone (closed by either side or aborted).
//   - Every socket gets TCP_NODELAY (QAbstractSocket::LowDelayOption).
//   - The socket is a QSslSocket in server mode (TlsServer): only decrypted bytes reach the frame reader. A failed
//     TLS handshake (a client that does not speak TLS 1.3, a bad record) emits tlsFailed(reason) and aborts the
//     connection; nothing of the ShapeCast protocol was read or sent on it.
//   - A control frame longer than kMaxControlMessageSize emits oversizeMessage() (then the usual refusal or
//     protocolError(), and the connection is closed): the reader never buffers more than one maximum frame.

#include "session/engine/handshake_host.h"
#include "session/engine/host_engine_actions.h"
#include "session/wire/control_frame.h"
#include "session/wire/model_transfer.h"

#include <QtCore/QObject>
#include <QtCore/QPointer>
#include <QtNetwork/QHostAddress>

#include <memory>
#include <optional>

class QTcpSocket;

namespace sc::session {

inline constexpr qint64 kTransferHighWater = 256 * 1024;  ///< chunks are written only below this many queued bytes

class HostPeerConnection final : public QObject {
  Q_OBJECT
  Q_DISABLE_COPY_MOVE(HostPeerConnection)

 public:
  /// Takes ownership of `socket` (re-parented to this). `now`: the accept time (the handshake timeout's origin).
  HostPeerConnection(QTcpSocket* socket, HostHandshakeConfig config, Millis now, QObject* parent = nullptr);
  ~HostPeerConnection() override;

  /// The id offered in the Welcome (fixed at accept time).
  [[nodiscard]] PeerId peerId() const { return m_peerId; }
  [[nodiscard]] bool isWelcomed() const { return m_handshake.state() == HostHandshake::State::Welcomed; }
  /// The joined peer (name, datagram key, path token); set once welcomed.
  [[nodiscard]] const std::optional<NegotiatedPeer>& peer() const { return m_handshake.peer(); }
  [[nodiscard]] bool isClosing() const { return m_closing; }
  /// Session clock of the last byte received (or of the accept).
  [[nodiscard]] Millis lastHeard() const { return m_lastHeard; }
  [[nodiscard]] QHostAddress peerAddress() const;

  /// Encodes and sends one message; does nothing once closing. A value that breaks a limit is not sent.
  void send(const ControlMessage& message);
  /// Sends one already encoded frame (encodeControlMessage()), e.g. a broadcast encoded once for every peer.
  void sendEncoded(const QByteArray& frame);
  /// Drives the handshake's timeout (call often while not welcomed).
  void tickHandshake(Millis now);
  /// Sends sender->begin() and then its chunks as the socket drains; transferFinished() after the last chunk.
  void startTransfer(std::unique_ptr<ModelSender> sender);
  [[nodiscard]] bool isTransferring() const { return m_transfer != nullptr; }

  /// Writes that would queue more than `bytes` are refused (see the contracts). Default: kSendBudgetBytes.
  void setSendBudget(qint64 bytes) { m_sendBudget = bytes; }
  /// The outgoing queue as measured now (for HostEngine::onSendQueue).
  [[nodiscard]] SendQueueReport sendQueue() const;
  /// Bytes written but not yet taken by the kernel: plaintext not yet encrypted plus TLS records queued.
  [[nodiscard]] qint64 queuedBytes() const;

  /// Flushes what is queued, then closes (aborts after a grace period if the peer does not read).
  void close();
  /// Drops the connection at once.
  void abort();

 signals:
  void welcomed();
  void refused(sc::session::RefuseReason reason);
  void messageReceived(const sc::session::ControlMessage& message);
  void protocolError(sc::session::ControlError error);
  void tlsFailed(const QString& reason);
  void oversizeMessage();
  void transferFinished(std::uint32_t transferId);
  void closed();

 private:
  void readAvailable();
  void handleHandshakeResult(const HandshakeOutput& out);
  void pumpTransfer();
  void onDisconnected();
  void onDrained();

  QPointer<QTcpSocket> m_socket;
  ControlFrameReader m_reader;
  PeerId m_peerId;  ///< declared before m_handshake: initialised from the config before it is moved there
  HostHandshake m_handshake;
  std::unique_ptr<ModelSender> m_transfer;
  Millis m_lastHeard;
  qint64 m_sendBudget = kSendBudgetBytes;
  qint64 m_peakQueued = 0;
  bool m_overBudget = false;
  Micros m_lastDrained;
  bool m_closing = false;
  bool m_closedEmitted = false;
};

}  // namespace sc::session
