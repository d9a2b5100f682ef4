#include "app/cli/relay_arguments.h"

#include "app/common/nats_url.h"
#include "session/wire/relay_message.h"

#include <QFileInfo>

#include <utility>

namespace sc::app {

RelayArguments::RelayArguments()
    : m_url(QStringLiteral("nats"), QStringLiteral("NATS server URL (nats://HOST:PORT; comma-separated for several)"),
            QStringLiteral("url")),
      m_user(QStringLiteral("nats-user"), QStringLiteral("NATS user name"), QStringLiteral("user")),
      m_password(QStringLiteral("nats-password"),
                 QStringLiteral("NATS password (visible in process lists: prefer --nats-password-file)"),
                 QStringLiteral("password")),
      m_passwordFile(QStringLiteral("nats-password-file"), QStringLiteral("NATS password: the first line of this file"),
                     QStringLiteral("file")),
      m_session(QStringLiteral("session"), QStringLiteral("session id on the relay (1..32 of A-Z a-z 0-9 _ -)"),
                QStringLiteral("id")),
      m_ca(QStringLiteral("nats-ca"),
           QStringLiteral("TLS to the broker (tls:// URL, or a server requiring TLS): trust the CA certificate(s) in "
                          "this PEM file instead of the system's"),
           QStringLiteral("file")) {}

void RelayArguments::addTo(SubcommandParser& command) const {
  command.parser().addOptions({m_url, m_user, m_password, m_passwordFile, m_session, m_ca});
}

bool RelayArguments::given(const SubcommandParser& command) const { return command.parser().isSet(m_url); }

std::optional<std::pair<session::NatsConnectOptions, QString>> RelayArguments::read(
    const SubcommandParser& command) const {
  const QCommandLineParser& parser = command.parser();
  session::NatsConnectOptions options;
  options.url = parser.value(m_url);
  options.user = parser.value(m_user);
  const QString sessionId = parser.value(m_session);
  if (options.url.isEmpty()) {
    command.error(QStringLiteral("--nats URL is required"));
    return std::nullopt;
  }
  if (const QString problem = natsUrlProblem(options.url); !problem.isEmpty()) {
    command.error(QStringLiteral("--nats: ") + problem);
    return std::nullopt;
  }
  options.caFile = parser.value(m_ca);
  if (!options.caFile.isEmpty() && !QFileInfo(options.caFile).isReadable()) {
    command.error(QStringLiteral("--nats-ca: cannot read %1").arg(options.caFile));
    return std::nullopt;
  }
  if (!session::isValidSessionId(sessionId)) {
    command.error(QStringLiteral("--session takes 1 to 32 of A-Z a-z 0-9 _ -"));
    return std::nullopt;
  }
  if (parser.isSet(m_passwordFile)) {
    std::optional<QString> password = readPasswordFile(command, parser.value(m_passwordFile));
    if (!password) return std::nullopt;
    options.password = std::move(*password);
  } else {
    options.password = parser.value(m_password);
  }
  return std::make_pair(std::move(options), sessionId);
}

bool RelayArguments::readPublisher(const SubcommandParser& command, const QString& connectionName,
                                   std::optional<session::RelayPublisherOptions>& publisher) const {
  if (!given(command)) return true;
  auto read = this->read(command);
  if (!read) return false;
  publisher.emplace();
  publisher->nats = std::move(read->first);
  publisher->nats.name = connectionName;
  publisher->sessionId = read->second;
  return true;
}

}  // namespace sc::app
