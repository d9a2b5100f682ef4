#include "app/gui/watch_settings.h"

#include "app/common/nats_url.h"
#include "session/wire/relay_message.h"

#include <QFileInfo>

namespace sc::app {

QString validateWatchSettings(const WatchSettings& settings) {
  const QString urlProblem = natsUrlProblem(settings.url);
  if (!urlProblem.isEmpty()) return QStringLiteral("--watch: ") + urlProblem;
  if (!session::isValidSessionId(settings.sessionId))
    return QStringLiteral("--session takes 1 to 32 of A-Z a-z 0-9 _ -");
  if (!settings.caFile.isEmpty() && !QFileInfo(settings.caFile).isReadable())
    return QStringLiteral("--nats-ca: cannot read %1").arg(settings.caFile);
  return {};
}

}  // namespace sc::app
