#pragma once
// The NATS relay options shared by `host` and `watch` (issue 18; README "Viewers through NATS"):
//   --nats URL  --nats-user U  (--nats-password P | --nats-password-file F)  --session ID  [--nats-ca CA.pem]
// A password on the command line shows in process lists: prefer --nats-password-file. URL tls://HOST:PORT (or a
// server that requires TLS): TLS to the broker, verified against --nats-ca (else the system's CAs). The URL syntax
// is the GUI's (app/common/nats_url.h).

#include "app/cli/cli_common.h"
#include "session/net/nats_client.h"
#include "session/net/relay_publisher.h"

#include <QCommandLineOption>
#include <QString>

#include <optional>

namespace sc::app {

class RelayArguments {
 public:
  RelayArguments();
  /// Adds the options to `command`'s parser (before parse()).
  void addTo(SubcommandParser& command) const;
  /// True when --nats was given.
  [[nodiscard]] bool given(const SubcommandParser& command) const;
  /// The connection options and session id; nullopt after command.error() (exit code kExitUsage) when one is missing
  /// or invalid.
  [[nodiscard]] std::optional<std::pair<session::NatsConnectOptions, QString>> read(
      const SubcommandParser& command) const;
  /// For a relaying host: `publisher` stays nullopt without --nats, else gets the publisher's options (the NATS
  /// connection named `connectionName`); false after command.error() (exit code kExitUsage) when an option is
  /// missing or invalid.
  [[nodiscard]] bool readPublisher(const SubcommandParser& command, const QString& connectionName,
                                   std::optional<session::RelayPublisherOptions>& publisher) const;

 private:
  QCommandLineOption m_url;
  QCommandLineOption m_user;
  QCommandLineOption m_password;
  QCommandLineOption m_passwordFile;
  QCommandLineOption m_session;
  QCommandLineOption m_ca;
};

}  // namespace sc::app
