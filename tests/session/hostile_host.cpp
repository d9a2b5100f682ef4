#include "hostile_host.h"

#include <QtCore/QFile>
#include <QtNetwork/QNetworkDatagram>

#include <unistd.h>

namespace sc::session::testing {

HostileHost::HostileHost(const TlsIdentity& identity) {
  m_server.setSslConfiguration(hostTlsConfiguration(identity.certificate, identity.privateKey));
  QObject::connect(&m_server, &QTcpServer::newConnection, &m_server, [this] { accept(); });
  m_server.listen(QHostAddress::LocalHost, 0);
  m_udp.bind(QHostAddress::LocalHost, 0);
}

HostileHost::~HostileHost() {
  if (m_client != nullptr) {
    m_client->abort();
    delete m_client;
  }
}

void HostileHost::accept() {
  QTcpSocket* next = m_server.nextPendingConnection();
  if (next == nullptr) return;
  if (m_client != nullptr) {  // one client per test
    next->abort();
    next->deleteLater();
    return;
  }
  m_client = static_cast<QSslSocket*>(next);
  m_client->setParent(nullptr);
  QObject::connect(m_client, &QTcpSocket::readyRead, m_client, [this] { readAvailable(); });
}

void HostileHost::readAvailable() {
  m_reader.append(m_client->readAll());
  while (auto result = m_reader.next()) {
    if (result->error == ControlError::None) m_received.push_back(std::move(result->message));
  }
}

bool HostileHost::awaitHello() { return take<Hello>().has_value(); }

void HostileHost::send(const ControlMessage& message) {
  if (m_client != nullptr) m_client->write(encodeControlMessage(message));
}

int HostileHost::streamChunks(std::uint32_t id, std::uint32_t totalSize, int count, int chunkBytes) {
  const QByteArray bytes(chunkBytes, 'z');
  int written = 0;
  while (written < count && !clientClosed(0)) {
    if (m_client->bytesToWrite() > (1 << 20)) {
      QTest::qWait(1);
      continue;
    }
    const auto offset = static_cast<std::uint32_t>(written) * static_cast<std::uint32_t>(chunkBytes);
    if (offset + static_cast<std::uint32_t>(chunkBytes) > totalSize) break;
    send(ModelChunk{id, offset, totalSize, bytes});
    ++written;
  }
  return written;
}

bool HostileHost::sendDatagrams(const std::vector<QByteArray>& datagrams) {
  if (!QTest::qWaitFor([this] { return m_udp.hasPendingDatagrams(); }, kHostileWaitMs)) return false;
  const QNetworkDatagram pathOpen = m_udp.receiveDatagram();
  for (const QByteArray& datagram : datagrams)
    m_udp.writeDatagram(datagram, pathOpen.senderAddress(), pathOpen.senderPort());
  return true;
}

bool HostileHost::clientClosed(int timeoutMs) {
  const auto closed = [this] { return m_client == nullptr || m_client->state() == QAbstractSocket::UnconnectedState; };
  return closed() || (timeoutMs > 0 && QTest::qWaitFor(closed, timeoutMs));
}

std::uint64_t residentBytes() {
  QFile statm(QStringLiteral("/proc/self/statm"));
  if (!statm.open(QIODevice::ReadOnly)) return 0;
  const QList<QByteArray> fields = statm.readAll().split(' ');
  return fields.size() > 1 ? fields[1].toULongLong() * static_cast<std::uint64_t>(::sysconf(_SC_PAGESIZE)) : 0;
}

}  // namespace sc::session::testing
