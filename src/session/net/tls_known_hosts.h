#pragma once
// How a client decides to trust the certificate a host shows (docs/security.md, "Host authentication"): a
// fingerprint given by the user (pinned) must match exactly; without one, trust on first use (TOFU, as SSH does):
// the first fingerprint seen for host:port is remembered in KnownHosts, and a different one later is refused with
// a readable reason until the user pins the new one explicitly.

#include <QtCore/QByteArray>
#include <QtCore/QString>

#include <optional>

namespace sc::session {

/// Remembered fingerprints per "host:port" (host as the user typed it), in QSettings group "knownHosts".
class KnownHosts {
 public:
  /// `file` empty: the application's default QSettings (organisation and application names); otherwise that INI
  /// file (tests). Cost: QSettings reads the store lazily; each call below is one lookup or one write.
  explicit KnownHosts(QString file = {});

  /// The QSettings group of the entries ("knownHosts"): one key per host:port, the fingerprint as its value.
  static QString settingsGroup() { return QStringLiteral("knownHosts"); }

  [[nodiscard]] std::optional<QByteArray> lookup(const QString& host, quint16 port) const;
  void remember(const QString& host, quint16 port, const QByteArray& fingerprint);
  void forget(const QString& host, quint16 port);

 private:
  QString m_file;
};

/// The verdict on a presented certificate fingerprint.
struct FingerprintCheck {
  enum class Verdict { Pinned, Known, FirstUse, Untrusted, Mismatch, Changed };
  Verdict verdict = Verdict::Untrusted;
  QString reason;  ///< for Mismatch and Changed: one readable paragraph for the user (both fingerprints)

  [[nodiscard]] bool accepted() const {
    return verdict == Verdict::Pinned || verdict == Verdict::Known || verdict == Verdict::FirstUse ||
           verdict == Verdict::Untrusted;
  }
};

/// Decides on `presented` (SHA-256 of the host's certificate): `pinned` non-empty → Pinned when equal, else
/// Mismatch; otherwise `remembered` (the TOFU entry, nullopt when none or TOFU is off): equal → Known, different
/// → Changed, none → FirstUse when `trustOnFirstUse`, else Untrusted (accepted: the password proof's channel
/// binding still stops relays, docs/security.md). Pure; O(1).
FingerprintCheck checkFingerprint(const QByteArray& presented, const QByteArray& pinned,
                                  const std::optional<QByteArray>& remembered, bool trustOnFirstUse);

}  // namespace sc::session
