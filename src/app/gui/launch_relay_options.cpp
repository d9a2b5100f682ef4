#include "app/gui/launch_relay_options.h"

#include "app/gui/host_relay_settings.h"

#include <QFile>

#include <utility>

namespace sc::app {

RelayLaunchOptions::RelayLaunchOptions()
    : m_url(QStringLiteral("nats"),
            QStringLiteral("With --host: also relay every frame through the NATS server at <url> (nats://HOST:PORT)."),
            QStringLiteral("url")),
      m_session(QStringLiteral("session"),
                QStringLiteral("With --nats or --watch: the relayed session's id (1 to 32 of A-Z a-z 0-9 _ -)."),
                QStringLiteral("id")),
      m_user(QStringLiteral("nats-user"),
             QStringLiteral("With --nats or --watch: the NATS user (the host's or a viewer's)."),
             QStringLiteral("user")),
      m_password(QStringLiteral("nats-password"),
                 QStringLiteral("With --nats or --watch: the NATS password (visible in process lists: prefer "
                                "--nats-password-file)."),
                 QStringLiteral("password")),
      m_passwordFile(QStringLiteral("nats-password-file"),
                     QStringLiteral("With --nats or --watch: the NATS password, the first line of <file>."),
                     QStringLiteral("file")),
      m_ca(QStringLiteral("nats-ca"),
           QStringLiteral("With --nats or --watch: TLS to the broker (tls://… URL, or a server requiring TLS) trusts "
                          "the CA certificate(s) in <file> (PEM) instead of the system's."),
           QStringLiteral("file")) {}

void RelayLaunchOptions::addTo(QCommandLineParser& parser) const {
  parser.addOptions({m_url, m_session, m_user, m_password, m_passwordFile, m_ca});
}

bool RelayLaunchOptions::given(const QCommandLineParser& parser) const {
  return parser.isSet(m_url) || parser.isSet(m_session) || parser.isSet(m_user) || parser.isSet(m_password) ||
         parser.isSet(m_passwordFile) || parser.isSet(m_ca);
}

bool RelayLaunchOptions::urlGiven(const QCommandLineParser& parser) const { return parser.isSet(m_url); }

std::variant<RelayCredentials, QString> RelayLaunchOptions::readCredentials(const QCommandLineParser& parser) const {
  RelayCredentials credentials{parser.value(m_session), parser.value(m_user), {}, parser.value(m_ca)};
  if (parser.isSet(m_password) && parser.isSet(m_passwordFile))
    return QStringLiteral("--nats-password and --nats-password-file cannot be used together");
  if (!parser.isSet(m_passwordFile)) {
    credentials.password = parser.value(m_password);
    return credentials;
  }
  QFile file(parser.value(m_passwordFile));
  if (!file.open(QIODevice::ReadOnly))
    return QStringLiteral("cannot read the NATS password file (--nats-password-file) %1").arg(file.fileName());
  credentials.password = QString::fromUtf8(file.readLine(4096)).trimmed();
  if (credentials.password.isEmpty())
    return QStringLiteral("the NATS password file (--nats-password-file) %1 is empty").arg(file.fileName());
  return credentials;
}

std::variant<std::optional<HostRelaySettings>, QString> RelayLaunchOptions::read(
    const QCommandLineParser& parser) const {
  if (!given(parser)) return std::optional<HostRelaySettings>();
  if (!parser.isSet(m_url) || parser.value(m_url).isEmpty())
    return QStringLiteral("--session, --nats-user, --nats-password[-file] and --nats-ca need --nats URL");
  const std::variant<RelayCredentials, QString> credentials = readCredentials(parser);
  if (const QString* problem = std::get_if<QString>(&credentials)) return *problem;
  const RelayCredentials& given = std::get<RelayCredentials>(credentials);
  HostRelaySettings relay{parser.value(m_url), given.sessionId, given.user, given.password, given.caFile};
  if (const std::optional<RelayProblem> problem = checkHostRelaySettings(relay))
    return QString(relayOptionName(problem->field) + QStringLiteral(": ") + problem->message);
  return std::optional<HostRelaySettings>(std::move(relay));
}

}  // namespace sc::app
