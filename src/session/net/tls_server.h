#pragma once
// A QTcpServer whose accepted sockets are QSslSockets that start the TLS server handshake at once with the given
// configuration (the host's certificate and key, TLS 1.3 only). Unlike QSslServer (Qt 6.4), a connection is
// handed out (nextPendingConnection()) as soon as it is accepted, before its handshake ends, so that SessionHost
// sees every unauthenticated connection: it applies its limits (pending handshakes, per address) and its one
// deadline to the TLS handshake and the ShapeCast handshake together. Reads and writes before the TLS handshake
// ends are held by QSslSocket: readyRead() only ever delivers decrypted bytes, and written bytes leave encrypted.

#include <QtNetwork/QSslConfiguration>
#include <QtNetwork/QTcpServer>

namespace sc::session {

class TlsServer final : public QTcpServer {
  Q_OBJECT
  Q_DISABLE_COPY_MOVE(TlsServer)

 public:
  explicit TlsServer(QObject* parent = nullptr);
  ~TlsServer() override;

  /// Configuration of the sockets accepted from now on (local certificate, private key, protocol).
  void setSslConfiguration(const QSslConfiguration& configuration) { m_configuration = configuration; }

 protected:
  /// Wraps the descriptor in a QSslSocket (child of this server until taken), starts server encryption and adds it
  /// to the pending connections. A descriptor Qt cannot adopt is closed.
  void incomingConnection(qintptr descriptor) override;

 private:
  QSslConfiguration m_configuration;
};

/// The server configuration for `certificate` and `key`: TLS 1.3 or later, no client certificate requested.
QSslConfiguration hostTlsConfiguration(const class QSslCertificate& certificate, const class QSslKey& key);

/// The client configuration: TLS 1.3 or later; the peer's certificate is not checked against certificate
/// authorities (the host's is self-signed) but pinned by its fingerprint after the handshake (SessionClient).
QSslConfiguration clientTlsConfiguration();

}  // namespace sc::session
