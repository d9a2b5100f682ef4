#pragma once
// Checking a host's relay settings (issue 18; session_settings.h HostRelaySettings): ONE rule for the command line
// (`shapecast --host … --nats URL …`, launch_relay_options.h) and the Host… dialog's "Relay viewers through NATS"
// group (host_dialog.h), so both accept and refuse the same values with the same words.

#include "app/gui/session_settings.h"

#include <QString>

#include <optional>

namespace sc::app {

/// The field of HostRelaySettings a problem is about (the dialog focuses it, the command line names its option).
enum class RelayField { Url, SessionId, User, Password, CaFile };

struct RelayProblem {
  RelayField field = RelayField::Url;
  QString message;  ///< one readable sentence
};

/// nullopt when `relay` can be tried; otherwise the first problem: the URL (app/common/nats_url.h), the session id
/// (session::isValidSessionId()), a user without a password, a CA file that cannot be read. Whether the server
/// answers and accepts the credentials only the attempt tells (HostController: hosting goes on without the relay
/// and says why).
std::optional<RelayProblem> checkHostRelaySettings(const HostRelaySettings& relay);

/// The command-line option of `field`: --nats, --session, --nats-user, --nats-password[-file], --nats-ca.
QString relayOptionName(RelayField field);

/// A fresh session id for the dialog's default: 10 random characters of a-z and 0-9 (QRandomGenerator::system()),
/// valid for session::isValidSessionId().
QString generateRelaySessionId();

}  // namespace sc::app
