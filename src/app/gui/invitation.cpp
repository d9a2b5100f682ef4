#include "app/gui/invitation.h"

#include "session/net/tls_identity.h"

#include <QCoreApplication>
#include <QHostAddress>
#include <QNetworkInterface>

namespace sc::app {

QString invitationText(const QString& address, quint16 port, const QByteArray& fingerprint) {
  if (fingerprint.isEmpty() || port == 0 || address.isEmpty()) return {};
  const QString hostPort = address.contains(QLatin1Char(':')) ? QStringLiteral("[%1]:%2").arg(address).arg(port)
                                                              : QStringLiteral("%1:%2").arg(address).arg(port);
  const auto translated = [](const char* text) { return QCoreApplication::translate("MainWindow", text); };
  return translated(
             "ShapeCast session at %1\nCertificate fingerprint: %2\nJoin with: shapecast --join %1 --fingerprint %3\n")
      .arg(hostPort, session::formatFingerprint(fingerprint), QString::fromLatin1(fingerprint.toHex()));
}

QString reachableAddress() {
  QString ipv6;
  for (const QNetworkInterface& candidate : QNetworkInterface::allInterfaces()) {
    const auto flags = candidate.flags();
    if (!flags.testFlag(QNetworkInterface::IsUp) || flags.testFlag(QNetworkInterface::IsLoopBack)) continue;
    for (const QNetworkAddressEntry& entry : candidate.addressEntries()) {
      const QHostAddress ip = entry.ip();
      if (ip.protocol() == QAbstractSocket::IPv4Protocol) return ip.toString();
      if (ipv6.isEmpty() && ip.protocol() == QAbstractSocket::IPv6Protocol && !ip.isLinkLocal()) ipv6 = ip.toString();
    }
  }
  return ipv6.isEmpty() ? QStringLiteral("127.0.0.1") : ipv6;
}

}  // namespace sc::app
