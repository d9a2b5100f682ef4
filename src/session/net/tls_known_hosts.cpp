#include "session/net/tls_known_hosts.h"

#include "session/net/tls_identity.h"

#include <QtCore/QSettings>

#include <memory>

namespace sc::session {
namespace {

std::unique_ptr<QSettings> open(const QString& file) {
  return file.isEmpty() ? std::make_unique<QSettings>() : std::make_unique<QSettings>(file, QSettings::IniFormat);
}

QString key(const QString& host, quint16 port) {
  // '/' separates QSettings groups; IPv6 addresses are bracketed as in URLs.
  const QString name = host.contains(QLatin1Char(':')) ? QStringLiteral("[%1]").arg(host) : host;
  return QStringLiteral("%1/%2:%3")
      .arg(KnownHosts::settingsGroup(), QString(name).replace(QLatin1Char('/'), QLatin1Char('_')))
      .arg(port);
}

}  // namespace

KnownHosts::KnownHosts(QString file) : m_file(std::move(file)) {}

std::optional<QByteArray> KnownHosts::lookup(const QString& host, quint16 port) const {
  const QString stored = open(m_file)->value(key(host, port)).toString();
  return stored.isEmpty() ? std::nullopt : parseFingerprint(stored);
}

void KnownHosts::remember(const QString& host, quint16 port, const QByteArray& fingerprint) {
  open(m_file)->setValue(key(host, port), formatFingerprint(fingerprint));
}

void KnownHosts::forget(const QString& host, quint16 port) { open(m_file)->remove(key(host, port)); }

FingerprintCheck checkFingerprint(const QByteArray& presented, const QByteArray& pinned,
                                  const std::optional<QByteArray>& remembered, bool trustOnFirstUse) {
  using V = FingerprintCheck::Verdict;
  if (!pinned.isEmpty()) {
    if (presented == pinned) return {V::Pinned, {}};
    return {V::Mismatch, QStringLiteral("the host's certificate fingerprint is %1, not the expected %2. Someone may "
                                        "be intercepting the connection, or the fingerprint was mistyped: compare it "
                                        "with the one the host shows. Not joined.")
                             .arg(formatFingerprint(presented), formatFingerprint(pinned))};
  }
  if (remembered) {
    if (presented == *remembered) return {V::Known, {}};
    return {V::Changed, QStringLiteral("the host's certificate fingerprint changed: it is now %1, it was %2 when you "
                                       "first joined this address. Someone may be intercepting the connection, or "
                                       "the host has a new certificate: compare with the fingerprint the host "
                                       "shows and, if it matches, join with that fingerprint. Not joined.")
                            .arg(formatFingerprint(presented), formatFingerprint(*remembered))};
  }
  return {trustOnFirstUse ? V::FirstUse : V::Untrusted, {}};
}

}  // namespace sc::session
