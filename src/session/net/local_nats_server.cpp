#include "session/net/local_nats_server.h"

#include "session/net/tls_identity.h"

#include <QtCore/QDir>
#include <QtCore/QElapsedTimer>
#include <QtCore/QFile>
#include <QtCore/QFileInfo>
#include <QtCore/QJsonArray>
#include <QtCore/QJsonDocument>
#include <QtCore/QJsonObject>
#include <QtCore/QProcess>
#include <QtCore/QStandardPaths>
#include <QtCore/QTemporaryDir>
#include <QtCore/QThread>
#include <QtCore/QUrl>

#include <optional>
#include <utility>

namespace sc::session {
namespace {

QString quoted(const QString& text) { return QLatin1Char('"') + text + QLatin1Char('"'); }

QString list(const QStringList& items) {
  QStringList out;
  for (const QString& item : items) out << quoted(item);
  return QLatin1Char('[') + out.join(QStringLiteral(", ")) + QLatin1Char(']');
}

/// Writes `bytes` to `path` (owner-only when `secret`); false with `error` set on failure.
bool writeFile(const QString& path, const QByteArray& bytes, bool secret, QString* error) {
  QFile file(path);
  if (!file.open(QIODevice::WriteOnly | QIODevice::Truncate) ||
      (secret && !file.setPermissions(QFile::ReadOwner | QFile::WriteOwner)) || file.write(bytes) != bytes.size()) {
    if (error) *error = QStringLiteral("cannot write %1").arg(path);
    return false;
  }
  return true;
}

/// The server's certificate and key (and the CA's certificate) in `dir`, unless they are there already.
bool writeServerCertificates(NatsServerTls tls, const QDir& dir, QString* error) {
  const QString certificatePath = dir.filePath(QStringLiteral("server-cert.pem"));
  if (QFile::exists(certificatePath)) return true;
  CertificateProfile server;
  server.commonName = QStringLiteral("localhost");
  server.dnsNames = {QStringLiteral("localhost")};
  server.ipAddresses = {QStringLiteral("127.0.0.1")};
  std::optional<TlsIdentity> ca;
  if (tls == NatsServerTls::CaSigned) {
    CertificateProfile authority;
    authority.commonName = QStringLiteral("ShapeCast test broker CA");
    authority.certificateAuthority = true;
    ca = generateTlsIdentity(authority, nullptr, error);
    if (!ca) return false;
  }
  const std::optional<TlsIdentity> identity = generateTlsIdentity(server, ca ? &*ca : nullptr, error);
  if (!identity) return false;
  const QByteArray trusted = ca ? ca->certificate.toPem() : identity->certificate.toPem();
  return writeFile(dir.filePath(QStringLiteral("server-key.pem")), identity->privateKey.toPem(), true, error) &&
         writeFile(dir.filePath(QStringLiteral("ca.pem")), trusted, false, error) &&
         writeFile(certificatePath, identity->certificate.toPem(), false, error);
}

}  // namespace

QString natsServerConfigText(const NatsServerConfig& config, int port, const QString& storeDir, const QString& tlsDir) {
  const QString sid = config.sessionId;
  const QString stream = QStringLiteral("KV_sc_") + sid;
  const QString levels = QStringLiteral("SC_%1_LEVELS").arg(sid);  // relay_level_list.h: read-only for viewers
  const QStringList hostPublish = {QStringLiteral("sc.%1.>").arg(sid),
                                   QStringLiteral("$KV.sc_%1.>").arg(sid),
                                   QStringLiteral("$JS.API.STREAM.CREATE.") + stream,
                                   QStringLiteral("$JS.API.STREAM.UPDATE.") + stream,
                                   QStringLiteral("$JS.API.STREAM.INFO.") + stream,
                                   QStringLiteral("$JS.API.STREAM.CREATE.") + levels,
                                   QStringLiteral("$JS.API.STREAM.UPDATE.") + levels,
                                   QStringLiteral("$JS.API.STREAM.INFO.") + levels};
  const QStringList hostSubscribe = {QStringLiteral("_INBOX.>"), QStringLiteral("sc.%1.stats.>").arg(sid)};
  const QStringList viewerPublish = {
      QStringLiteral("$JS.API.STREAM.INFO.") + stream, QStringLiteral("$JS.API.STREAM.MSG.GET.") + stream,
      QStringLiteral("$JS.API.DIRECT.GET.") + stream + QStringLiteral(".>"), QStringLiteral("sc.%1.stats.>").arg(sid),
      QStringLiteral("$JS.API.STREAM.MSG.GET.") + levels};
  const QStringList viewerSubscribe = {QStringLiteral("sc.%1.z").arg(sid), QStringLiteral("_INBOX.>")};
  QString tls;
  if (config.tls != NatsServerTls::None && !tlsDir.isEmpty()) {
    const QDir dir(tlsDir);
    tls = QStringLiteral("tls {\n  cert_file: %1\n  key_file: %2\n  timeout: 2\n}\n")
              .arg(quoted(dir.filePath(QStringLiteral("server-cert.pem"))),
                   quoted(dir.filePath(QStringLiteral("server-key.pem"))));
  }
  auto user = [](const QString& name, const QString& password, const QStringList& pub, const QStringList& sub) {
    return QStringLiteral("    { user: %1, password: %2, permissions: { publish: %3, subscribe: %4 } }\n")
        .arg(quoted(name), quoted(password), list(pub), list(sub));
  };
  return QStringLiteral("listen: 127.0.0.1:%1\n").arg(port == 0 ? -1 : port) +
         QStringLiteral("jetstream { store_dir: %1 }\n").arg(quoted(storeDir)) +
         QStringLiteral("write_deadline: \"2s\"\nmax_pending: 8MB\n") +
         QStringLiteral("authorization {\n  users = [\n") +
         user(config.hostUser, config.hostPassword, hostPublish, hostSubscribe) +
         user(config.viewerUser, config.viewerPassword, viewerPublish, viewerSubscribe) + QStringLiteral("  ]\n}\n") +
         tls;
}

QString natsServerBinary() {
  const QString given = qEnvironmentVariable("SHAPECAST_NATS_SERVER");
  if (!given.isEmpty()) return QFileInfo(given).isExecutable() ? given : QString();
  const QString onPath = QStandardPaths::findExecutable(QStringLiteral("nats-server"));
  if (!onPath.isEmpty()) return onPath;
  return QStandardPaths::findExecutable(QStringLiteral("nats-server"),
                                        {QStringLiteral("/usr/sbin"), QStringLiteral("/usr/bin")});
}

bool natsServerAvailable() { return !natsServerBinary().isEmpty(); }

LocalNatsServer::LocalNatsServer(NatsServerConfig config)
    : m_config(std::move(config)), m_dir(std::make_unique<QTemporaryDir>()) {}

LocalNatsServer::~LocalNatsServer() { stop(); }

QString LocalNatsServer::directory() const { return m_dir->path(); }

QString LocalNatsServer::caFile() const {
  return m_config.tls == NatsServerTls::None ? QString() : QDir(m_dir->path()).filePath(QStringLiteral("ca.pem"));
}

bool LocalNatsServer::running() const { return m_process && m_process->state() == QProcess::Running; }

bool LocalNatsServer::start(QString* error, std::chrono::milliseconds wait) {
  auto fail = [this, error](const QString& why) {
    if (error) *error = why;
    stop();
    return false;
  };
  if (running()) return true;
  if (!m_dir->isValid()) return fail(QStringLiteral("no temporary folder"));
  const QString binary = natsServerBinary();
  if (binary.isEmpty()) return fail(QStringLiteral("nats-server is not installed"));
  const QDir dir(m_dir->path());
  for (const QString& old : dir.entryList({QStringLiteral("*.ports")}, QDir::Files)) QFile::remove(dir.filePath(old));
  const QString configPath = dir.filePath(QStringLiteral("nats.conf"));
  QFile file(configPath);
  if (!file.open(QIODevice::WriteOnly | QIODevice::Truncate)) return fail(QStringLiteral("cannot write the config"));
  if (m_config.tls != NatsServerTls::None) {
    QString why;
    if (!writeServerCertificates(m_config.tls, dir, &why)) return fail(QStringLiteral("TLS certificates: ") + why);
  }
  file.write(natsServerConfigText(m_config, m_port, dir.filePath(QStringLiteral("js")), dir.path()).toUtf8());
  file.close();

  m_process = std::make_unique<QProcess>();
  m_process->setProcessChannelMode(QProcess::MergedChannels);
  m_process->setStandardOutputFile(dir.filePath(QStringLiteral("nats-server.log")), QIODevice::Append);
  m_process->start(binary, {QStringLiteral("-c"), configPath, QStringLiteral("--ports_file_dir"), dir.path()});
  if (!m_process->waitForStarted(2000)) return fail(QStringLiteral("nats-server did not start"));
  m_pid = m_process->processId();
  const QString portsPath = dir.filePath(QStringLiteral("nats-server_%1.ports").arg(m_pid));
  QElapsedTimer clock;
  clock.start();
  while (clock.elapsed() < wait.count()) {
    QFile ports(portsPath);
    if (ports.open(QIODevice::ReadOnly)) {
      const QJsonArray urls = QJsonDocument::fromJson(ports.readAll()).object().value(QStringLiteral("nats")).toArray();
      const QUrl url(urls.isEmpty() ? QString() : urls.first().toString());
      if (url.isValid() && url.port() > 0) {
        m_port = url.port();
        m_url = QStringLiteral("%1://127.0.0.1:%2")
                    .arg(m_config.tls == NatsServerTls::None ? QStringLiteral("nats") : QStringLiteral("tls"))
                    .arg(m_port);
        return true;
      }
    }
    if (m_process->state() != QProcess::Running) return fail(QStringLiteral("nats-server exited; see its log"));
    QThread::msleep(20);
  }
  return fail(QStringLiteral("nats-server wrote no ports file within %1 ms").arg(wait.count()));
}

void LocalNatsServer::stop() {
  if (!m_process) return;
  if (m_process->state() != QProcess::NotRunning) {
    m_process->terminate();  // SIGTERM to m_pid
    if (!m_process->waitForFinished(2000)) {
      m_process->kill();
      m_process->waitForFinished(2000);
    }
  }
  m_process.reset();
}

bool LocalNatsServer::restart(QString* error) {
  stop();
  return start(error);
}

}  // namespace sc::session
