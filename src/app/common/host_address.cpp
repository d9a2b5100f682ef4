#include "app/common/host_address.h"

#include <QRegularExpression>

namespace sc::app {

std::optional<HostAddress> parseHostAddress(const QString& text) {
  // A bracketed host, or one without whitespace or brackets (greedy: a bare IPv6 address keeps all but the last
  // colon); then the port.
  static const QRegularExpression pattern(QStringLiteral("^(\\[[^\\]\\s]+\\]|[^\\s\\[\\]]+):(\\d{1,5})$"));
  const QRegularExpressionMatch match = pattern.match(text);
  if (!match.hasMatch()) return std::nullopt;
  const uint port = match.captured(2).toUInt();
  if (port == 0 || port > 65535) return std::nullopt;
  QString host = match.captured(1);
  if (host.startsWith(QLatin1Char('['))) host = host.mid(1, host.size() - 2);
  return HostAddress{host, static_cast<quint16>(port)};
}

}  // namespace sc::app
