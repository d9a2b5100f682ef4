#pragma once
// What the Host… and Join… dialogs remember between runs (QSettings, group "sessions"): recent mesh paths, host
// addresses, ports and display names, most recent first, and the Host… dialog's relay group (issue 18). Passwords are
// never stored.

#include "app/gui/session_settings.h"

#include <QSettings>
#include <QString>
#include <QStringList>

namespace sc::app {

/// At most this many entries per list.
inline constexpr int kMaxRecentEntries = 10;

struct RecentSessions {
  QStringList meshPaths;   ///< hosted meshes
  QStringList hosts;       ///< joined host addresses
  QStringList names;       ///< display names used
  int hostPort = 47100;    ///< last TCP port hosted on
  int joinPort = 47100;    ///< last TCP port joined
  int frequencies = 100;   ///< last m hosted with
  int joinResolution = 0;  ///< index of the last resolution chosen in the Join dialog
  // The Host… dialog's "Relay viewers through NATS" group (HostRelaySettings without the password).
  bool relayEnabled = false;  ///< the last hosting relayed
  QString relayUrl;           ///< the last NATS URL relayed through
  QString relaySessionId;     ///< the last relay session id (the dialog makes a new one when empty)
  QString relayUser;          ///< the last NATS user
  QString relayCaFile;        ///< the last broker CA file

  /// Reads the remembered values from `settings` (defaults for missing or malformed ones).
  static RecentSessions load(QSettings& settings);
  /// Writes them back (never a password: none is held here).
  void save(QSettings& settings) const;
  /// Moves `value` to the front of `list` (trimmed; empty values ignored; at most kMaxRecentEntries kept).
  static void remember(QStringList& list, const QString& value);
  /// Records a hosting attempt's mesh path, port, m and name, and whether it relayed (with its URL, session id, user
  /// and CA file; the relay values are kept when it did not relay, for the next time).
  void rememberHost(const HostSettings& settings);
  /// Records a join attempt's host, port and name.
  void rememberJoin(const JoinSettings& settings);
};

}  // namespace sc::app
