#include "app/gui/host_relay_settings.h"

#include "app/common/nats_url.h"
#include "session/wire/relay_message.h"

#include <QFileInfo>
#include <QRandomGenerator>

namespace sc::app {

std::optional<RelayProblem> checkHostRelaySettings(const HostRelaySettings& relay) {
  const QString urlProblem = natsUrlProblem(relay.url.trimmed());
  if (!urlProblem.isEmpty()) return RelayProblem{RelayField::Url, urlProblem};
  if (!session::isValidSessionId(relay.sessionId)) {
    return RelayProblem{RelayField::SessionId, QStringLiteral("The relay session id must be 1 to 32 of A-Z a-z 0-9 _ - "
                                                              "(viewers watch the session by this id).")};
  }
  if (!relay.user.isEmpty() && relay.password.isEmpty())
    return RelayProblem{RelayField::Password, QStringLiteral("Enter the NATS password of user “%1”.").arg(relay.user)};
  if (!relay.caFile.isEmpty()) {
    const QFileInfo file(relay.caFile);
    if (!file.isFile() || !file.isReadable()) {
      return RelayProblem{
          RelayField::CaFile,
          QStringLiteral("The CA file “%1” (the broker's certificate authority) cannot be read.").arg(relay.caFile)};
    }
  }
  return std::nullopt;
}

QString relayOptionName(RelayField field) {
  switch (field) {
    case RelayField::Url:
      return QStringLiteral("--nats");
    case RelayField::SessionId:
      return QStringLiteral("--session");
    case RelayField::User:
      return QStringLiteral("--nats-user");
    case RelayField::Password:
      return QStringLiteral("--nats-password[-file]");
    case RelayField::CaFile:
      return QStringLiteral("--nats-ca");
  }
  return {};
}
QString generateRelaySessionId() {
  static constexpr char kAlphabet[] = "abcdefghijklmnopqrstuvwxyz0123456789";
  constexpr int kLength = 10;
  QString id;
  id.reserve(kLength);
  for (int i = 0; i < kLength; ++i)
    id.append(QLatin1Char(kAlphabet[QRandomGenerator::system()->bounded(static_cast<int>(sizeof kAlphabet - 1))]));
  return id;
}

}  // namespace sc::app
