#pragma once
// The host's settings and counters (HostEngine, host_engine.h): what the rules are configured with and what they
// counted. SessionHostOptions (net/session_host.h) derives from HostEngineOptions and adds the sockets' settings.

#include "session/engine/constraint_work.h"
#include "session/engine/handshake_host.h"
#include "session/engine/host_engine_actions.h"
#include "session/engine/host_engine_rate_limit.h"
#include "session/engine/session_clock.h"
#include "session/wire/control_messages.h"
#include "spectral/spectral_deformer.h"

#include <QtCore/QString>

#include <array>
#include <chrono>
#include <cstddef>
#include <cstdint>

namespace sc::session {

inline constexpr Micros kHousekeepingPeriod{100'000};  ///< handshake deadlines, lock lease, own renew, idle refresh
inline constexpr Micros kHeartbeatPeriod{1'000'000};
/// The longest a lock holder keeps the lock while others wait (HostEngineOptions::maxLockHoldWhileWaited).
inline constexpr Millis kMaxLockHoldWhileWaited{60000};
/// Addresses whose wrong passwords the host remembers at once (the oldest is forgotten first).
inline constexpr std::size_t kMaxTrackedAddresses = 4096;

/// A clock reading in whole milliseconds (what the lock arbiter, the handshakes and lastHeard count in).
inline Millis toMillis(Micros t) { return std::chrono::duration_cast<Millis>(t); }

/// The host's rules (SessionHostOptions derives from it and adds the sockets' settings).
struct HostEngineOptions {
  QString hostName = QStringLiteral("host");  ///< the host's own PeerList entry (peer 1)
  int maxPeers = 16;  ///< clients at once, 1..kMaxPeers − 1 (the PeerList also holds the host)
  /// Edit leases at once (people dragging at once, each their own handle groups), 1..kMaxPeers; 1 = one lock.
  int maxEditors = 1;
  spectral::DeformerOptions deformer;
  int referenceEvery = 15;  ///< a Keyframe to every loaded peer each this many frames; 1 = every frame; 0 = never
  std::chrono::milliseconds idleRefresh{1000};   ///< repeat the current Z when nothing moved for this long
  std::chrono::milliseconds coalesce{8};         ///< minimum spacing of drag frames
  std::chrono::milliseconds peerTimeout{10000};  ///< a peer silent this long is dropped
  /// One still frame after the last moving frame (still_frame_schedule.h); false: none (e.g. a test emulating the
  /// loss of the still frame).
  bool stillFrame = true;
  int maxPendingHandshakes = 16;  ///< unauthenticated connections at once, ≥ 1
  int maxPendingPerAddress = 8;   ///< unauthenticated connections at once from one IP address, ≥ 1
  std::chrono::milliseconds handshakeTimeout = kHandshakeTimeout;  ///< TLS + Hello + password proof, from accept
  // A hostile member or stranger (docs/security.md, "Hostile member"); rates are per peer.
  std::int64_t sendBudgetBytes = kSendBudgetBytes;   ///< a peer with more bytes queued for it is dropped
  std::chrono::milliseconds sendStallTimeout{3000};  ///< a peer whose queue has not drained for this long is dropped
  RateLimit messageRate{500.0, 1000.0};              ///< every message after the Welcome; over it: dropped (flood)
  RateLimit lockRequestRate{4.0, 8.0};               ///< LockRequest{Request}; over it: ignored
  RateLimit resolutionRequestRate{2.0, 6.0};         ///< ResolutionRequest; over it: ignored
  RateLimit constraintsRate{4.0, 4.0};               ///< Constraints; over it: rejected
  RateLimit editRequestRate{4.0, 8.0};               ///< EditRequest (undo / redo); over it: ignored
  RateLimit presenceRate{30.0, 30.0};                ///< Presence relayed per peer; over it: dropped, never closed
  /// Constraints whose (handle + anchor ids) · m² exceeds this are rejected: bounds the refactoring's work and its
  /// ids × m temporary (30000 ids at m = 128: 90–150 ms on one core, off the network thread; 31 MB).
  double maxConstraintWork = kMaxConstraintWork;
  /// The lock holder is revoked after holding this long while others wait (from the grant, or from when the queue
  /// became non-empty, whichever is later); 0 = never.
  std::chrono::milliseconds maxLockHoldWhileWaited = kMaxLockHoldWhileWaited;
  /// Wrong passwords from one address (admission key) before the next connection from it must wait; each further
  /// one doubles the wait from wrongPasswordBackoff up to maxWrongPasswordBackoff.
  int freeWrongPasswords = 3;
  std::chrono::milliseconds wrongPasswordBackoff{1000};
  std::chrono::milliseconds maxWrongPasswordBackoff{60000};
};

/// What the host rejected or dropped, for tests and the UI.
struct HostEngineCounters {
  std::array<std::uint64_t, kRefuseReasonLast + 1> refusals{};  ///< indexed by RefuseReason's wire value
  std::uint64_t protocolErrors = 0;  ///< decode errors or unexpected messages after the Welcome (connection closed)
  std::uint64_t dragsAccepted = 0;
  std::uint64_t dragsNotHolder = 0;
  std::uint64_t dragsStale = 0;
  std::uint64_t constraintsAccepted = 0;
  std::uint64_t constraintsRejected = 0;     ///< lock verdict, or ids ≥ n / empty groups, or overlapping
  std::uint64_t constraintsOverlapping = 0;  ///< refused with LockNotice{Refused}: another holder's, or too many
  std::uint64_t silentPeersDropped = 0;
  std::uint64_t framesSent = 0;
  std::uint64_t keyframesSent = 0;
  std::uint64_t stillFramesSent = 0;  ///< still frames (included in framesSent), see StillFrameSchedule
  std::uint64_t transfersCompleted = 0;
  std::uint64_t tlsFailures = 0;             ///< TLS handshakes that failed (e.g. a client not speaking TLS)
  std::uint64_t connectionsOverLimit = 0;    ///< aborted at accept: too many unauthenticated connections
  std::uint64_t oversizeMessages = 0;        ///< control frames longer than kMaxControlMessageSize (closed)
  std::uint64_t slowPeersDropped = 0;        ///< over the send budget, or not reading for sendStallTimeout
  std::int64_t peakSendQueueBytes = 0;       ///< the largest queue reported for any peer (bytes not yet sent)
  std::uint64_t requestsThrottled = 0;       ///< lock / resolution requests and Constraints over their rate (ignored)
  std::uint64_t floodingPeersDropped = 0;    ///< peers over messageRate (closed)
  std::uint64_t pendingEvicted = 0;          ///< pending connections closed to make room for another address
  std::uint64_t connectionsThrottled = 0;    ///< aborted at accept: the address is waiting after wrong passwords
  std::uint64_t wrongPasswords = 0;          ///< wrong password proofs (each logged with its address)
  std::uint64_t locksRevokedForWaiters = 0;  ///< holders revoked after maxLockHoldWhileWaited with others waiting
  std::uint64_t strokesCommitted = 0;        ///< edit steps recorded (strokes that changed the shape)
  std::uint64_t editsApplied = 0;            ///< undo / redo requests that changed the shape
  std::uint64_t editsRefused = 0;            ///< undo / redo requests with nothing to undo / redo
  std::uint64_t presenceRelayed = 0;         ///< members' Presence messages relayed (host_engine_presence.cpp)
  std::uint64_t presenceDropped = 0;         ///< members' Presence messages over presenceRate (dropped)

  [[nodiscard]] std::uint64_t refusalsFor(RefuseReason reason) const {
    return refusals[static_cast<std::size_t>(reason)];
  }
};

}  // namespace sc::session
