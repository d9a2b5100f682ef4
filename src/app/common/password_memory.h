#pragma once
// How the front ends (shapecast-cli, the desktop app) let go of a session password once the session object holds
// it: the password is needed only until SessionHost::start() derives its key (PBKDF2) or, for a client, until its
// proof; the front end's own copy should not outlive that (docs/security.md, "Files, command line and deformation
// range").

#include <QString>

#include <optional>

namespace sc::app {

/// Drops this holder's copy of a password: its characters are overwritten in place when no one else shares the
/// buffer (another holder's copy, e.g. the session's own, is left to that holder), then the optional is reset.
/// O(length).
void forgetPassword(std::optional<QString>& password);

}  // namespace sc::app
