#include "app/common/nats_url.h"

#include "app/common/host_address.h"

#include <QStringList>

namespace sc::app {
namespace {

/// Empty when `url` is one valid server URL; otherwise why not.
QString oneUrlProblem(const QString& url) {
  const QString example = QStringLiteral("nats://127.0.0.1:4222 or tls://broker.example.org:4222");
  if (url.isEmpty()) return QStringLiteral("Enter the NATS URL, e.g. %1.").arg(example);
  const qsizetype scheme = url.indexOf(QStringLiteral("://"));
  const QString name = scheme < 0 ? QString() : url.left(scheme).toLower();
  if (name != QStringLiteral("nats") && name != QStringLiteral("tls"))
    return QStringLiteral("The NATS URL “%1” must start with nats:// or tls://, e.g. %2.").arg(url, example);
  QString rest = url.mid(scheme + 3);
  if (rest.endsWith(QLatin1Char('/'))) rest.chop(1);
  if (rest.contains(QLatin1Char('@')))
    return QStringLiteral("The NATS URL “%1” holds a user or password: give them in their own fields.").arg(url);
  if (rest.contains(QLatin1Char('/')) || rest.contains(QLatin1Char('?')) || rest.contains(QLatin1Char('#')))
    return QStringLiteral("The NATS URL “%1” must be only the server and its port, e.g. %2.").arg(url, example);
  const bool hasPort =
      rest.startsWith(QLatin1Char('[')) ? rest.contains(QStringLiteral("]:")) : rest.count(QLatin1Char(':')) == 1;
  // Without a port, cnats uses 4222: check the host alone with a placeholder port.
  if (!parseHostAddress(hasPort ? rest : rest + QStringLiteral(":4222")))
    return QStringLiteral("The NATS URL “%1” needs a server name or address and a port from 1 to 65535, e.g. %2.")
        .arg(url, example);
  return {};
}

}  // namespace

QString natsUrlProblem(const QString& urls) {
  const QStringList list = urls.split(QLatin1Char(','));
  for (const QString& url : list) {
    const QString problem = oneUrlProblem(url.trimmed());
    if (!problem.isEmpty()) return problem;
  }
  return {};
}

}  // namespace sc::app
