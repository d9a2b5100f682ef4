#pragma once
// The options every client command (join, drive) takes, parsed in one place so that both trust a host the same way
// (docs/security.md, "Host authentication"): --name, --password-file and --fingerprint. Without --fingerprint the
// client trusts on first use: the first certificate seen for HOST:PORT is remembered (KnownHosts, the application's
// QSettings) and a different one later is refused before any password proof is sent.

#include "app/cli/cli_common.h"
#include "session/net/session_client.h"

#include <QCommandLineOption>
#include <QString>

namespace sc::app {

class PeerArguments {
 public:
  /// Adds --name (default `defaultName`), --password-file and --fingerprint to `command`'s parser; call before
  /// command.parse().
  PeerArguments(SubcommandParser& command, const QString& defaultName);

  /// After a successful parse(): fills `options`' host, port, name, password, pinned fingerprint and sets
  /// trustOnFirstUse. Prints the problem through command.error() and returns false for a malformed fingerprint or
  /// an unreadable or empty password file (a usage error). Cost: one small file read.
  [[nodiscard]] bool apply(const SubcommandParser& command, session::SessionClientOptions& options) const;

 private:
  QCommandLineOption m_name;
  QCommandLineOption m_passwordFile;
  QCommandLineOption m_fingerprint;
};

}  // namespace sc::app
