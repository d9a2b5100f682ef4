#include "app/cli/peer_arguments.h"

#include "session/net/tls_identity.h"

namespace sc::app {

PeerArguments::PeerArguments(SubcommandParser& command, const QString& defaultName)
    : m_name(QStringLiteral("name"), QStringLiteral("display name (default: %1)").arg(defaultName),
             QStringLiteral("name"), defaultName),
      m_passwordFile(QStringLiteral("password-file"), QStringLiteral("session password: the first line of this file"),
                     QStringLiteral("file")),
      m_fingerprint(QStringLiteral("fingerprint"),
                    QStringLiteral("the host's certificate fingerprint (SHA-256, as the host prints it); without it "
                                   "the first one seen for this address is remembered and a different one later is "
                                   "refused"),
                    QStringLiteral("hex")) {
  command.parser().addOptions({m_name, m_passwordFile, m_fingerprint});
}

bool PeerArguments::apply(const SubcommandParser& command, session::SessionClientOptions& options) const {
  const QCommandLineParser& p = command.parser();
  options.host = command.peerHost();
  options.port = command.peerPort();
  options.name = p.value(m_name);
  options.trustOnFirstUse = true;
  if (p.isSet(m_fingerprint)) {
    const std::optional<QByteArray> pinned = session::parseFingerprint(p.value(m_fingerprint));
    if (!pinned) {
      command.error(QStringLiteral("--fingerprint takes 64 hex digits (colons allowed), as the host prints it"));
      return false;
    }
    options.fingerprint = *pinned;
  }
  if (p.isSet(m_passwordFile)) {
    options.password = readPasswordFile(command, p.value(m_passwordFile));
    if (!options.password) return false;
  }
  return true;
}

}  // namespace sc::app
