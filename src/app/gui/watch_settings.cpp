#include "app/gui/watch_settings.h"

#include "session/wire/relay_message.h"

namespace sc::app {

QString validateWatchSettings(const WatchSettings& settings) {
  if (!settings.url.startsWith(QStringLiteral("nats://")) && !settings.url.startsWith(QStringLiteral("tls://")))
    return QStringLiteral("--watch takes a NATS URL such as nats://127.0.0.1:4222");
  if (!session::isValidSessionId(settings.sessionId))
    return QStringLiteral("--session takes 1 to 32 of A-Z a-z 0-9 _ -");
  return {};
}

}  // namespace sc::app
