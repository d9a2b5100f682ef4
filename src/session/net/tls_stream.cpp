// TlsStream: the buffer shared by the two threads, the worker that owns the QSslSocket on the stream thread, and the
// owner's side (commands queued to the worker, reads from the buffer, signals re-emitted on the owner's thread).

#include "session/net/tls_stream.h"

#include <QtCore/QMutex>
#include <QtCore/QMutexLocker>
#include <QtCore/QThread>
#include <QtCore/QVariant>
#include <QtNetwork/QSslSocket>

#include <openssl/crypto.h>

#include <algorithm>
#include <deque>
#include <utility>

namespace sc::session {

namespace {
/// The buffer's chunks are allocated this large and filled by the socket's reads (QSslSocket decrypts 4 KiB records
/// and QIODevice::readAll leaves 16–32 KiB of capacity behind each: kept as they come, 64 MiB of such reads took
/// 516 MiB of heap).
constexpr qsizetype kChunkBytes = 256 * 1024;
}  // namespace

/// What both threads touch, under `mutex`: the decrypted bytes (a queue of chunks of kChunkBytes capacity, the
/// first one read from `frontOffset`), their bound, the readyRead hand-shake, and what the connection reported.
struct TlsStream::Buffer {
  mutable QMutex mutex;
  std::deque<QByteArray> chunks;
  qsizetype frontOffset = 0;
  qint64 bytes = 0;
  qint64 limit = kDefaultReadLimit;
  bool readyPosted = false;     ///< a readyRead is on its way to the owner
  bool waitingForRoom = false;  ///< the worker stopped reading at `limit`: the owner's next read wakes it
  QHostAddress peer;
  QSslCertificate certificate;

  /// Appends `got` to the last chunk while it has room (no reallocation), else starts a chunk.
  void append(const QByteArray& got) {
    if (chunks.empty() || chunks.back().size() + got.size() > chunks.back().capacity()) {
      chunks.emplace_back();
      chunks.back().reserve(std::max(kChunkBytes, got.size()));
    }
    chunks.back().append(got);
    bytes += got.size();
  }

  /// Up to `maxBytes` bytes from the front. Cost: a copy, except when one whole chunk is taken.
  QByteArray take(qint64 maxBytes) {
    const qint64 wanted = std::min(maxBytes, bytes);
    if (wanted <= 0) return {};
    QByteArray out;
    if (frontOffset == 0 && chunks.front().size() == wanted) {
      out = std::move(chunks.front());
      chunks.pop_front();
    } else {
      out.reserve(wanted);
      while (out.size() < wanted) {
        QByteArray& front = chunks.front();
        const qsizetype piece = std::min<qsizetype>(front.size() - frontOffset, wanted - out.size());
        out.append(front.constData() + frontOffset, piece);
        frontOffset += piece;
        if (frontOffset == front.size()) {
          chunks.pop_front();
          frontOffset = 0;
        }
      }
    }
    bytes -= wanted;
    return out;
  }
};

/// Lives on the stream thread; every member runs there.
class TlsStream::Worker final : public QObject {
 public:
  Worker(TlsStream* owner, std::shared_ptr<Buffer> buffer, QSslConfiguration configuration)
      : m_owner(owner), m_buffer(std::move(buffer)), m_configuration(std::move(configuration)) {}

  /// The socket, made here on first use (so that its notifiers belong to this thread); nullptr once closed.
  QSslSocket* socket() {
    if (m_socket == nullptr && !m_closed) makeSocket();
    return m_socket;
  }

  /// Moves the socket's decrypted bytes into the buffer while it holds fewer than its limit (all of them when
  /// `everything`: the connection has ended); tells the owner once per batch.
  void drain(bool everything) {
    if (m_socket == nullptr) return;
    bool moved = false;
    while (true) {
      const qint64 available = m_socket->bytesAvailable();
      if (available <= 0) break;
      qint64 room = available;
      if (!everything) {
        QMutexLocker lock(&m_buffer->mutex);
        room = m_buffer->limit - m_buffer->bytes;
        m_buffer->waitingForRoom = room <= 0;
        if (room <= 0) break;
      }
      // read(n) allocates n first: never more than is there. A read makes QSslSocket decrypt what waits.
      QByteArray got = room >= available ? m_socket->readAll() : m_socket->read(room);
      if (got.isEmpty()) break;
      QMutexLocker lock(&m_buffer->mutex);
      m_buffer->append(got);
      moved = true;
    }
    if (!moved) return;
    QMutexLocker lock(&m_buffer->mutex);
    if (m_buffer->readyPosted) return;
    m_buffer->readyPosted = true;
    lock.unlock();
    post([owner = m_owner] { owner->deliverReadyRead(); });
  }

  /// Ends the socket without a signal; nothing reopens it.
  void close() {
    m_closed = true;
    if (m_socket == nullptr) return;
    m_socket->disconnect(this);
    m_socket->abort();
    delete m_socket;
    m_socket = nullptr;
  }

  void setSocketBuffer(qint64 bytes) {
    m_socketBuffer = bytes;
    if (QSslSocket* s = socket()) s->setReadBufferSize(bytes);
  }
  void setReceiveBuffer(qint64 bytes) { m_receiveBuffer = bytes; }

 private:
  void makeSocket() {
    m_socket = new QSslSocket(this);
    m_socket->setSslConfiguration(m_configuration);
    m_socket->setReadBufferSize(m_socketBuffer);
    connect(m_socket, &QSslSocket::connected, this, [this] {
      m_socket->setSocketOption(QAbstractSocket::LowDelayOption, 1);
      if (m_receiveBuffer > 0) {
        m_socket->setSocketOption(QAbstractSocket::ReceiveBufferSizeSocketOption, QVariant::fromValue(m_receiveBuffer));
      }
      QMutexLocker lock(&m_buffer->mutex);
      m_buffer->peer = m_socket->peerAddress();
      lock.unlock();
      post([owner = m_owner] { emit owner->connected(); });
    });
    connect(m_socket, &QSslSocket::encrypted, this, [this] {
      QMutexLocker lock(&m_buffer->mutex);
      m_buffer->certificate = m_socket->peerCertificate();
      lock.unlock();
      post([owner = m_owner] { emit owner->encrypted(); });
    });
    connect(m_socket, &QSslSocket::readyRead, this, [this] { drain(false); });
    connect(m_socket, &QSslSocket::errorOccurred, this, [this](QAbstractSocket::SocketError error) {
      post([owner = m_owner, error, text = m_socket->errorString()] { emit owner->errorOccurred(error, text); });
    });
    connect(m_socket, &QSslSocket::disconnected, this, [this] {
      drain(true);  // what the host sent before closing (its Leave) goes before the news of the close
      post([owner = m_owner] { emit owner->disconnected(); });
    });
  }

  /// Runs `call` on the owner's thread (dropped if the owner is gone by then).
  template <class Call>
  void post(Call call) {
    QMetaObject::invokeMethod(m_owner, std::move(call), Qt::QueuedConnection);
  }

  TlsStream* m_owner;
  std::shared_ptr<Buffer> m_buffer;
  QSslConfiguration m_configuration;
  QSslSocket* m_socket = nullptr;
  qint64 m_socketBuffer = kDefaultSocketBuffer;
  qint64 m_receiveBuffer = 0;
  bool m_closed = false;
};

TlsStream::TlsStream(QSslConfiguration configuration, QObject* parent)
    : QObject(parent), m_buffer(std::make_shared<Buffer>()) {
  m_thread = new QThread;
  m_thread->setObjectName(QStringLiteral("tls-stream"));
  m_worker = new Worker(this, m_buffer, std::move(configuration));
  m_worker->moveToThread(m_thread);
  // OpenSSL keeps state per thread (its error queue), freed by a thread-exit handler that runs after the thread's
  // function returns, so possibly after wait() in the destructor: a process that exits then loses it (LeakSanitizer
  // found 10 KB in 3 of 12 runs of a test). Freed here instead, on the thread, before wait() can return.
  connect(
      m_thread, &QThread::finished, m_thread, [] { OPENSSL_thread_stop(); }, Qt::DirectConnection);
  m_thread->start();
}

TlsStream::~TlsStream() {
  QMetaObject::invokeMethod(
      m_worker,
      [worker = m_worker] {
        worker->close();
        worker->moveToThread(nullptr);  // deleted below, on this (the owner's) thread
      },
      Qt::BlockingQueuedConnection);
  m_thread->quit();
  m_thread->wait();
  delete m_worker;
  delete m_thread;
}

namespace {

/// Runs `call(worker)` on the stream thread, after the calls queued before it.
template <class Worker, class Call>
void queue(Worker* worker, Call call) {
  QMetaObject::invokeMethod(
      worker, [worker, call = std::move(call)] { call(*worker); }, Qt::QueuedConnection);
}

/// Runs `call(socket)` on the stream thread if the socket is there (made on first use; none once closed).
template <class Worker, class Call>
void queueOnSocket(Worker* worker, Call call) {
  queue(worker, [call = std::move(call)](Worker& w) {
    if (QSslSocket* socket = w.socket()) call(*socket);
  });
}

}  // namespace

void TlsStream::connectToHostEncrypted(const QString& host, quint16 port) {
  queueOnSocket(m_worker, [host, port](QSslSocket& socket) { socket.connectToHostEncrypted(host, port); });
}

void TlsStream::write(const QByteArray& bytes) {
  queueOnSocket(m_worker, [bytes](QSslSocket& socket) {
    if (socket.state() == QAbstractSocket::ConnectedState) socket.write(bytes);
  });
}

void TlsStream::disconnectFromHost() {
  queueOnSocket(m_worker, [](QSslSocket& socket) { socket.disconnectFromHost(); });
}

void TlsStream::abort() {
  queueOnSocket(m_worker, [](QSslSocket& socket) { socket.abort(); });
}

void TlsStream::setBufferSizes(qint64 readLimit, qint64 socketBuffer) {
  {
    QMutexLocker lock(&m_buffer->mutex);
    m_buffer->limit = std::max<qint64>(readLimit, 1);
  }
  queue(m_worker, [socketBuffer = std::max<qint64>(socketBuffer, 1)](Worker& worker) {
    worker.setSocketBuffer(socketBuffer);
    worker.drain(false);  // a larger limit makes room
  });
}

void TlsStream::setReceiveBufferSize(qint64 bytes) {
  queue(m_worker, [bytes](Worker& worker) { worker.setReceiveBuffer(bytes); });
}

qint64 TlsStream::bytesAvailable() const {
  QMutexLocker lock(&m_buffer->mutex);
  return m_buffer->bytes;
}

QByteArray TlsStream::read(qint64 maxBytes) {
  QMutexLocker lock(&m_buffer->mutex);
  QByteArray out = m_buffer->take(maxBytes);
  const bool wake = m_buffer->waitingForRoom && m_buffer->bytes < m_buffer->limit;
  if (wake) m_buffer->waitingForRoom = false;
  lock.unlock();
  if (wake) queue(m_worker, [](Worker& worker) { worker.drain(false); });
  return out;
}

QByteArray TlsStream::readAll() { return read(bytesAvailable()); }

qint64 TlsStream::readLimit() const {
  QMutexLocker lock(&m_buffer->mutex);
  return m_buffer->limit;
}

QHostAddress TlsStream::peerAddress() const {
  QMutexLocker lock(&m_buffer->mutex);
  return m_buffer->peer;
}

QSslCertificate TlsStream::peerCertificate() const {
  QMutexLocker lock(&m_buffer->mutex);
  return m_buffer->certificate;
}

void TlsStream::deliverReadyRead() {
  {
    QMutexLocker lock(&m_buffer->mutex);
    m_buffer->readyPosted = false;  // bytes buffered from now on announce themselves again
  }
  emit readyRead();
}

}  // namespace sc::session
