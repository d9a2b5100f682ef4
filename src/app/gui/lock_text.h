#pragma once
// The lock line and the lock button of a session window's toolbar, from the lock state machine's view of this user
// (docs/protocol.md, "Lock"): who holds the lock, who waits for it and where this user stands. Formatting only.
// Cost: O(#peers · #waiting) (the queue is bounded by kMaxPeers; at most kMaxWaitingNames names are spelled out).

#include "session/engine/lock_client.h"
#include "session/wire/control_messages.h"

#include <QString>

namespace sc::app {

/// Names spelled out in "bob, carol and 2 others are waiting".
inline constexpr int kMaxWaitingNames = 3;

/// "You hold the lock", "Lock free" or "Lock held by NAME" (the peer's name, else "peer N"; with several holders
/// "Locks held by NAME and NAME", and a holder reads " — NAME drags too"), plus " — requesting…",
/// " — you are 2nd in the queue" or " — releasing…" while this user waits or releases; the holder reads who waits
/// (" — bob is waiting", " — bob and carol are waiting", " — bob, carol, dan and 2 others are waiting"), and a user
/// whose lock the host took back reads " — the host released your lock" until it asks again.
/// @param[in] lock  this user's lock client; holders those holding a lock (empty: free); self this user.
[[nodiscard]] QString lockText(const session::LockClient& lock, const std::vector<session::PeerId>& holders,
                               session::PeerId self, const session::PeerList& peers);

/// Why the host refused this user's handle and anchors: "Your handle or anchors overlap bob's: paint where nobody
/// else holds" or, with no holder named, "Too many handle and anchor vertices for everybody together: paint fewer".
[[nodiscard]] QString refusalText(const session::LockRefusal& refusal, const session::PeerList& peers);

/// The lock button's text: "Release lock" while holding (or releasing), "Cancel request" while requested or
/// queued, else "Request lock".
[[nodiscard]] QString lockActionText(const session::LockClient& lock);

}  // namespace sc::app
