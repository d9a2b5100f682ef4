#include "raw_control_peer.h"

#include "session/net/tls_server.h"

#include "session/net/tls_server.h"

#include <QtNetwork/QSslSocket>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

namespace sc::session::testing {

RawControlPeer::RawControlPeer(quint16 port, int receiveBufferBytes) : m_socket(std::make_unique<QSslSocket>()) {
  // The one place that chooses the transport: TLS 1.3 as SessionClient speaks it (any host certificate accepted;
  // pinning is SessionClient's). The tests only see send/take, in clear text above TLS.
  auto* tls = static_cast<QSslSocket*>(m_socket.get());
  tls->setSslConfiguration(clientTlsConfiguration());
  QObject::connect(m_socket.get(), &QTcpSocket::readyRead, m_socket.get(), [this] { readAvailable(); });
  if (receiveBufferBytes <= 0) {
    tls->connectToHostEncrypted(QHostAddress(QHostAddress::LocalHost).toString(), port);
    return;
  }
  // SO_RCVBUF must be set before connect() to bound the window the host sees: connect by hand, then adopt.
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  if (fd < 0) return;
  ::setsockopt(fd, SOL_SOCKET, SO_RCVBUF, &receiveBufferBytes, sizeof receiveBufferBytes);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_port = htons(port);
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  if (::connect(fd, reinterpret_cast<const sockaddr*>(&address), sizeof address) != 0 ||
      !m_socket->setSocketDescriptor(fd)) {
    ::close(fd);
    return;
  }
  tls->startClientEncryption();
}

RawControlPeer::~RawControlPeer() { m_socket->abort(); }

bool RawControlPeer::connected() {
  return QTest::qWaitFor([this] { return static_cast<QSslSocket*>(m_socket.get())->isEncrypted(); }, kRawWaitMs);
}

void RawControlPeer::send(const ControlMessage& message) { m_socket->write(encodeControlMessage(message)); }

void RawControlPeer::sendRaw(const QByteArray& bytes) { m_socket->write(bytes); }

bool RawControlPeer::closedByHost() {
  return QTest::qWaitFor([this] { return m_socket->state() == QAbstractSocket::UnconnectedState; }, kRawWaitMs);
}

void RawControlPeer::stopReading() {
  m_reading = false;
  m_socket->setReadBufferSize(1);  // Qt stops draining the kernel buffer once this much is buffered
}

void RawControlPeer::abort() { m_socket->abort(); }

std::optional<Welcome> RawControlPeer::join(const QString& name) {
  if (!connected()) return std::nullopt;
  send(Hello{kProtocolVersion, name});
  return take<Welcome>();
}

LockEpoch RawControlPeer::acquireLock(PeerId self) {
  send(LockMessage{LockRequestKind::Request, kNoEpoch});
  for (int i = 0; i < 10; ++i) {
    const std::optional<LockNotice> notice = take<LockNotice>();
    if (!notice) return kNoEpoch;
    if (notice->kind == LockNoticeKind::Granted && notice->peer == self) return notice->epoch;
  }
  return kNoEpoch;
}

void RawControlPeer::readAvailable() {
  if (!m_reading) return;
  m_reader.append(m_socket->readAll());
  while (auto result = m_reader.next()) {
    if (result->error != ControlError::None) continue;
    m_received.push_back(std::move(result->message));
  }
}

}  // namespace sc::session::testing
