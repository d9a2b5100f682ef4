#pragma once
// The lock line of a session window's toolbar, from the lock state machine's view of this user (docs/protocol.md,
// "Lock"): who holds the lock and where this user stands. Formatting only. Cost: O(#peers).

#include "session/engine/lock_client.h"
#include "session/wire/control_messages.h"

#include <QString>

namespace sc::app {

/// "You hold the lock", "Lock free" or "Lock held by NAME" (the peer's name, else "peer N"), plus " — requesting…",
/// " — you are 2nd in the queue" or " — releasing…" while this user waits or releases.
/// @param[in] lock  this user's lock client; holder the peer holding the lock (kNoPeer: free); self this user.
[[nodiscard]] QString lockText(const session::LockClient& lock, session::PeerId holder, session::PeerId self,
                               const session::PeerList& peers);

}  // namespace sc::app
