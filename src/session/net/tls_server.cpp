#include "session/net/tls_server.h"

#include <QtNetwork/QSslCertificate>
#include <QtNetwork/QSslKey>
#include <QtNetwork/QSslSocket>

#include <unistd.h>

namespace sc::session {

TlsServer::TlsServer(QObject* parent) : QTcpServer(parent) {}

TlsServer::~TlsServer() = default;

void TlsServer::incomingConnection(qintptr descriptor) {
  auto* socket = new QSslSocket(this);
  if (!socket->setSocketDescriptor(descriptor)) {
    delete socket;
    ::close(static_cast<int>(descriptor));  // not adopted: still ours to close
    return;
  }
  socket->setSslConfiguration(m_configuration);
  addPendingConnection(socket);
  socket->startServerEncryption();
}

QSslConfiguration hostTlsConfiguration(const QSslCertificate& certificate, const QSslKey& key) {
  QSslConfiguration configuration = QSslConfiguration::defaultConfiguration();
  configuration.setProtocol(QSsl::TlsV1_3OrLater);
  configuration.setLocalCertificate(certificate);
  configuration.setPrivateKey(key);
  configuration.setPeerVerifyMode(QSslSocket::VerifyNone);
  return configuration;
}

QSslConfiguration clientTlsConfiguration() {
  QSslConfiguration configuration = QSslConfiguration::defaultConfiguration();
  configuration.setProtocol(QSsl::TlsV1_3OrLater);
  configuration.setPeerVerifyMode(QSslSocket::VerifyNone);  // pinned by fingerprint instead (see header)
  return configuration;
}

}  // namespace sc::session
