#pragma once
// A local nats-server for tests, experiments and demos (issue 18; ../shared/design/scale-out.md, "Test fixture"):
// writes a configuration into a temporary folder (loopback only, JetStream stored in that folder, one host user and one
// viewer user with the relay's permissions: docs/security.md, "Relay credentials"), starts
// `nats-server -c <dir>/nats.conf --ports_file_dir <dir>` as a child process, reads its URL from the ports file it
// writes, and stops it by its PID. A plain `authorization { users = [...] }` block, never mixed with an `accounts`
// block (advisory GHSA-fr2g-9hjm-wr23 for the Debian server 2.9.10).

#include <QtCore/QByteArray>
#include <QtCore/QString>

#include <chrono>
#include <memory>

class QProcess;
class QTemporaryDir;

namespace sc::session {

/// The nats-server binary: $SHAPECAST_NATS_SERVER when set, else `nats-server` on PATH, in /usr/sbin (Debian
/// installs it there) or /usr/bin; empty when none.
QString natsServerBinary();

/// TLS between the clients and the server (docs/security.md, "TLS to the broker").
enum class NatsServerTls {
  None,        ///< plain nats://
  CaSigned,    ///< a generated CA (caFile()) signs the server's certificate (CN and SAN localhost, IP 127.0.0.1)
  SelfSigned,  ///< the server's certificate signs itself; caFile() is that certificate
};

/// The users and the session whose subjects they may use, and whether clients must use TLS.
struct NatsServerConfig {
  QString sessionId = QStringLiteral("test");
  QString hostUser = QStringLiteral("host");
  QString hostPassword = QStringLiteral("host-secret");
  QString viewerUser = QStringLiteral("viewer");
  QString viewerPassword = QStringLiteral("viewer-secret");
  NatsServerTls tls = NatsServerTls::None;
};

/// The configuration text: listen on 127.0.0.1:`port` (0: a random port, written as -1), JetStream under `storeDir`.
/// Host: publish sc.<sid>.> and its bucket's KV and JetStream API subjects, create/update/info of the level stream
/// SC_<sid>_LEVELS; subscribe its inboxes and the viewers' statistics. Viewer: subscribe sc.<sid>.z and its inboxes;
/// publish only the bucket's read API subjects, the level stream's message-get API and sc.<sid>.stats.> (so a
/// viewer's publish on the frame or a level subject is refused by the server). With `tlsDir` (config.tls not None):
/// a `tls {}` block with `tlsDir`/server-cert.pem and server-key.pem (every client must then use TLS).
QString natsServerConfigText(const NatsServerConfig& config, int port, const QString& storeDir,
                             const QString& tlsDir = {});

class LocalNatsServer {
 public:
  explicit LocalNatsServer(NatsServerConfig config = {});
  ~LocalNatsServer();  ///< stops the server
  LocalNatsServer(const LocalNatsServer&) = delete;
  LocalNatsServer& operator=(const LocalNatsServer&) = delete;

  /// Starts the server on `port` (0: random, the first time; a restart reuses the port) and waits up to `wait`
  /// for its ports file. With config().tls, the first start generates the certificates (OpenSSL, tls_identity.h:
  /// ECDSA P-256) into directory(); a restart keeps them. False with `error` set when the binary is missing, the
  /// certificates cannot be made, it exits or the file never comes.
  bool start(QString* error = nullptr, std::chrono::milliseconds wait = std::chrono::milliseconds(5000));
  /// Stops the server by its PID (SIGTERM, then SIGKILL after 2 s). Idempotent.
  void stop();
  /// stop(), then start() on the same port with the same JetStream folder.
  bool restart(QString* error = nullptr);

  [[nodiscard]] bool running() const;
  [[nodiscard]] QString url() const { return m_url; }  ///< nats://127.0.0.1:PORT (tls:// with config().tls)
  /// The PEM file a client trusts to verify the server (the CA, or the self-signed server certificate); empty
  /// without TLS.
  [[nodiscard]] QString caFile() const;
  [[nodiscard]] int port() const { return m_port; }
  [[nodiscard]] qint64 pid() const { return m_pid; }
  [[nodiscard]] QString directory() const;
  [[nodiscard]] const NatsServerConfig& config() const { return m_config; }
  /// Changes config().tls; only before the first start() (the certificates are made then).
  void setTls(NatsServerTls tls) { m_config.tls = tls; }

 private:
  NatsServerConfig m_config;
  std::unique_ptr<QTemporaryDir> m_dir;
  std::unique_ptr<QProcess> m_process;
  QString m_url;
  int m_port = 0;
  qint64 m_pid = 0;
};

/// True when natsServerBinary() found one (tests skip otherwise).
bool natsServerAvailable();

}  // namespace sc::session
