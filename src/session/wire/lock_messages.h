#pragma once
// Typed messages of the edit-lock protocol (issue 4, item 4), shared by the host's LockArbiter and the peer's
// LockClient. These are in-memory values, not a byte layout: the socket adapter encodes them through
// wire_format.h. Peer id 0 and epoch 0 are reserved ("nobody" / "no grant").
//
// Protocol in one picture (host arbitrates; every notice in []* is broadcast to all peers):
//
//   peer                         host
//   Request ----------------->   free?  yes: [Granted{peer, epoch}]*       no: Queued{peer, position} (to peer)
//   Renew{epoch} ------------>   holder with that epoch: lease extended     else ignored and counted
//   Release{epoch} ---------->   holder (epoch matches or 0): [Released{peer, epoch, Released}]* + next grant
//                                queued: Dequeued{peer} (to peer)           else ignored and counted
//   (3 s silence / disconnect)   [Released{peer, epoch, LeaseExpired | Disconnected}]* + next grant
//   (the host's user revokes)    [Released{peer, epoch, RevokedByHost}]* + next grant     (since version 4)
//   (the queue changed)          [Waiting{queue}]* : who waits, head first                (since version 4)
//   Constraints overlapping      Refused{peer, epoch, holders} (to peer): its handles touch the listed holders'
//   another holder's              handles or anchors, or (holders empty) everybody's together are too many
//                                                                                          (since version 5)
//
// Several peers may hold a lease at once (the host's "people dragging at once", since version 5): each Granted and
// Released names its own peer and epoch, and a newcomer is sent one Granted per current lease.
// Epochs strictly increase with every grant, so a drag stamped with an older epoch is recognisably stale
// (a fencing token).

#include <chrono>
#include <cstdint>
#include <vector>

namespace sc::session {

using PeerId = std::uint32_t;
using LockEpoch = std::uint32_t;
using Millis = std::chrono::milliseconds;  ///< injected monotonic clock reading, origin arbitrary

inline constexpr PeerId kNoPeer = 0;            ///< reserved: "nobody holds the lock"
inline constexpr PeerId kHostPeer = 1;          ///< the host's own user
inline constexpr LockEpoch kNoEpoch = 0;        ///< reserved: "never granted" / "whatever I hold or wait for"
inline constexpr Millis kLockLease{3000};       ///< host revokes after strictly more than this much silence
inline constexpr Millis kLockRenewEvery{1000};  ///< client renew period: three chances per lease

/// One current lease: its holder and epoch.
struct LockHolding {
  PeerId peer = kNoPeer;
  LockEpoch epoch = kNoEpoch;
  friend bool operator==(const LockHolding&, const LockHolding&) = default;
};

/// Peer → host.
enum class LockRequestKind : std::uint8_t { Request = 1, Release = 2, Renew = 3 };

struct LockMessage {
  LockRequestKind kind = LockRequestKind::Request;
  LockEpoch epoch = kNoEpoch;  ///< Renew: the held epoch; Release: the held epoch, or kNoEpoch to cancel anything
  friend bool operator==(const LockMessage&, const LockMessage&) = default;
};

/// Host → peer(s).
/// Waiting (since version 4): the queue changed; `waiting` lists the waiting peers, head first.
/// Refused (since version 5): the addressee's Constraints were refused; `waiting` lists the holders they overlap.
enum class LockNoticeKind : std::uint8_t {
  Granted = 1,
  Queued = 2,
  Released = 3,
  Dequeued = 4,
  Waiting = 5,
  Refused = 6
};
inline constexpr std::uint8_t kLockNoticeKindLast = 6;

/// Why a holder stopped holding. RevokedByHost (since version 4): the host's user took the lock back.
enum class LockReleaseReason : std::uint8_t { Released = 0, LeaseExpired = 1, Disconnected = 2, RevokedByHost = 3 };
inline constexpr std::uint8_t kLockReleaseReasonLast = 3;

struct LockNotice {
  LockNoticeKind kind = LockNoticeKind::Granted;
  PeerId peer = kNoPeer;       ///< Granted: new holder; Released: old holder; Queued/Dequeued/Refused: the addressee
  LockEpoch epoch = kNoEpoch;  ///< Granted/Released: the grant's epoch; Refused: the refused set's; else kNoEpoch
  std::uint32_t queuePosition = 0;                         ///< Queued: 1 = next in line; otherwise 0
  LockReleaseReason reason = LockReleaseReason::Released;  ///< Released only
  /// Waiting: the queue, head first; Refused: the holders the set overlaps (empty: the union would be too large);
  /// ≤ kMaxPeers (wire_format.h); empty for the other kinds.
  std::vector<PeerId> waiting{};
  friend bool operator==(const LockNotice&, const LockNotice&) = default;
};

}  // namespace sc::session
