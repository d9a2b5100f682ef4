#pragma once
// TlsStream: a TLS client connection whose socket lives on a thread of its own. The socket's reads from the kernel,
// the TLS decryption and the handshake run there; the owner (SessionClient, on the desktop app's GUI thread) reads
// the decrypted bytes from a bounded buffer. Why: a host drops a peer whose send queue has not drained for
// HostEngineOptions::sendStallTimeout (3 s), and a GUI thread that stands still that long (a first paint of a
// million vertices on software GL, a debugger, a slow machine) would stop the reads with it; now the stream thread
// keeps taking the host's bytes while the owner is busy, up to readLimit().
//
// Threads: construct, call and destroy a TlsStream on one thread (the owner's); its signals arrive there, in the
// socket's order (connected, encrypted, readyRead…, errorOccurred, disconnected), each after the state it reports
// (peerAddress(), peerCertificate(), the buffered bytes) is readable.
// Bounds: the stream thread moves decrypted bytes into the buffer while it holds fewer than readLimit(); then it
// stops reading, QSslSocket's own buffers fill (its decrypted buffer and the encrypted bytes it took from the
// kernel, each up to the socket buffer size of setBufferSizes()), and TCP's flow control backs up to the host, until
// the owner reads. Held: at most readLimit() + 3 socket buffer sizes, plus the last chunk's unused capacity
// (256 KiB). The bytes the socket still holds when the host closes are all moved (disconnected() follows them).
// One connection per stream: make a new TlsStream to connect again.
// Cost: one thread per stream; each received byte is copied once more than a read on the owner's thread.

#include <QtCore/QByteArray>
#include <QtCore/QObject>
#include <QtCore/QString>
#include <QtNetwork/QAbstractSocket>
#include <QtNetwork/QHostAddress>
#include <QtNetwork/QSslCertificate>
#include <QtNetwork/QSslConfiguration>

#include <memory>

class QThread;

namespace sc::session {

class TlsStream final : public QObject {
  Q_OBJECT
  Q_DISABLE_COPY_MOVE(TlsStream)

 public:
  /// Default readLimit(): 64 MiB, about 5 s of a 100 Mbit/s link, or a 1M-vertex level's first tenth on loopback.
  static constexpr qint64 kDefaultReadLimit = 64 * 1024 * 1024;
  /// Default socket buffer size (setBufferSizes()): QSslSocket's own buffers while this stream's buffer is full.
  static constexpr qint64 kDefaultSocketBuffer = 1024 * 1024;

  /// Starts the stream thread; the socket (with `configuration`) is made there on the first call that needs it.
  explicit TlsStream(QSslConfiguration configuration, QObject* parent = nullptr);
  /// Aborts the connection (no signal follows) and joins the stream thread. Cost: one round trip to that thread.
  ~TlsStream() override;

  // --- commands: queued to the stream thread, in call order

  /// QSslSocket::connectToHostEncrypted; at connection the socket gets TCP_NODELAY and receiveBufferSize() (if set).
  void connectToHostEncrypted(const QString& host, quint16 port);
  /// Queues `bytes` for the host (encrypted once the handshake ends); dropped unless the socket is connected then.
  void write(const QByteArray& bytes);
  /// Closes after the bytes written so far have left (QSslSocket::disconnectFromHost).
  void disconnectFromHost();
  /// Closes at once, dropping what was not sent (QSslSocket::abort).
  void abort();
  /// Bounds the buffer (`readLimit` > 0 bytes) and the socket's own (`socketBuffer` > 0 bytes); a smaller limit
  /// reads less from the host from now on, nothing buffered is dropped.
  void setBufferSizes(qint64 readLimit, qint64 socketBuffer);
  /// The kernel's receive buffer (SO_RCVBUF) set at connection; 0: the system's (autotuned).
  void setReceiveBufferSize(qint64 bytes);

  // --- the received bytes and what the connection reported (owner's thread)

  /// Decrypted bytes buffered and not yet read.
  [[nodiscard]] qint64 bytesAvailable() const;
  /// Takes up to `maxBytes` (≥ 0) buffered bytes, oldest first; may let the stream thread read more from the host.
  QByteArray read(qint64 maxBytes);
  /// Takes every buffered byte.
  QByteArray readAll();
  [[nodiscard]] qint64 readLimit() const;
  /// The host's address (null before connected()).
  [[nodiscard]] QHostAddress peerAddress() const;
  /// The certificate the host showed (null before encrypted()).
  [[nodiscard]] QSslCertificate peerCertificate() const;

 signals:
  void connected();
  void encrypted();
  /// New bytes were buffered: one signal for any number of them until the owner reads or handles this signal.
  void readyRead();
  void errorOccurred(QAbstractSocket::SocketError error, const QString& description);
  void disconnected();

 private:
  struct Buffer;
  class Worker;

  /// Clears the pending mark, then emits readyRead() (posted by the worker).
  void deliverReadyRead();

  std::shared_ptr<Buffer> m_buffer;
  QThread* m_thread = nullptr;
  Worker* m_worker = nullptr;
};

}  // namespace sc::session
