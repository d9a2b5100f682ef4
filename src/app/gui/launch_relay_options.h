#pragma once
// shapecast's relay options for a host (issue 18 item 3), parsed apart from the others (launch_options.h):
//
//   shapecast --host MESH --nats URL --session ID --nats-user U (--nats-password-file F | --nats-password P)
//             [--nats-ca CA.pem]
//
// The host then also publishes every frame once through the NATS server at URL (session::RelayPublisher), and its
// Peers and Statistics docks show the viewers as one aggregate. A viewer (`shapecast --watch URL`, watch_settings.h)
// shares --session, --nats-user and the password options (readCredentials()). A password given on the command line
// shows in process lists: prefer --nats-password-file (its first line).

#include "app/gui/session_settings.h"

#include <QCommandLineOption>
#include <QCommandLineParser>
#include <QString>

#include <optional>
#include <variant>

namespace sc::app {

/// What a relaying host and a viewer both give: the session id (not validated here), the NATS user and password.
struct RelayCredentials {
  QString sessionId;
  QString user;
  QString password;
  QString caFile;  ///< --nats-ca: the broker's CA to trust (TLS); empty: the system's
};

class RelayLaunchOptions {
 public:
  RelayLaunchOptions();
  /// Adds --nats, --session, --nats-user, --nats-password, --nats-password-file and --nats-ca to `parser`.
  void addTo(QCommandLineParser& parser) const;
  /// Whether any of them is set.
  [[nodiscard]] bool given(const QCommandLineParser& parser) const;
  /// Whether --nats is set (a host's relay; a viewer gives its URL with --watch).
  [[nodiscard]] bool urlGiven(const QCommandLineParser& parser) const;
  /// --session, --nats-user and the password (the first line of --nats-password-file, or --nats-password), or the
  /// problem in words: both password options, an unreadable or empty password file.
  [[nodiscard]] std::variant<RelayCredentials, QString> readCredentials(const QCommandLineParser& parser) const;
  /// The relay settings (nullopt when none of the options is set), or the problem in words: --nats missing while
  /// another relay option is set, both password options, an unreadable or empty password file, then what
  /// checkHostRelaySettings() refuses (a bad URL or --session, …), prefixed with the option's name.
  [[nodiscard]] std::variant<std::optional<HostRelaySettings>, QString> read(const QCommandLineParser& parser) const;

 private:
  QCommandLineOption m_url, m_session, m_user, m_password, m_passwordFile, m_ca;
};

}  // namespace sc::app
