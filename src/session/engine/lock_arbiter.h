#pragma once
// Host side of the edit-lock protocol: up to maxHolders leases at once (issue 15: several people drag at once, each
// their own handle groups; 1 = the paper's single lock), FIFO queue, lease, fencing epochs.
// A pure state machine: no sockets, no timers. The caller feeds it peer messages, disconnects and clock ticks
// (an injected monotonic `Millis`), and sends the returned LockEvents. Message kinds: see lock_messages.h.
//
// State: the holders {peer, epoch, lastHeard} in grant order (at most maxHolders) and a FIFO queue of waiting peers.
//
// Invariants (checked by tests after every step of a random run):
//   - at most maxHolders holders, each peer at most once, and a holder is never also in the queue; the queue holds
//     each peer at most once;
//   - the queue is non-empty only while every lease is taken (a release or revocation grants the head at once);
//   - every grant gets an epoch strictly greater than every earlier one (monotonic counter, never reused);
//   - a holder is revoked only when `now - lastHeard > lease` (strictly), checked at tick(), or at disconnect, or
//     (with maxHoldWhileWaited > 0) at tick() when others wait and it has held strictly longer than maxHoldWhileWaited
//     since the later of its grant and the moment the queue became non-empty (Released{LeaseExpired}: no new reason
//     on the wire; the longest-held lease goes first), so that renewing cannot keep the lock from waiting peers for
//     ever.
//
// Liveness: a Request, a Renew or an accepted drag from the holder refreshes lastHeard. Re-requests by the holder
// or a queued peer change nothing and only repeat the peer's Granted / Queued notice (idempotent).
// Out-of-order or stale messages (Renew from a non-holder, Release of an epoch not held, ...) are ignored and
// counted in ignoredMessages(), never asserted on (style.md item 6: network input).
//
// Cost: O(1) per message except queue removal (O(queue length), i.e. the number of peers).

#include <deque>
#include <optional>
#include <vector>

#include "session/wire/lock_messages.h"

namespace sc::session {

/// Who a notice goes to.
enum class LockAudience : std::uint8_t { AllPeers, OnePeer };

/// One notification the host must send. With AllPeers, `notice` goes to every connected peer.
struct LockEvent {
  LockAudience audience = LockAudience::AllPeers;
  PeerId recipient = kNoPeer;  ///< OnePeer only
  LockNotice notice;
  friend bool operator==(const LockEvent&, const LockEvent&) = default;
};

using LockEvents = std::vector<LockEvent>;

/// Verdict on a drag command stamped with an epoch.
enum class DragVerdict : std::uint8_t {
  Accepted,
  NotHolder,   ///< the sender does not hold the lock (or nobody does)
  StaleEpoch,  ///< the sender holds the lock, but the drag carries an epoch other than the current grant's
};

class LockArbiter {
 public:
  /// `maxHoldWhileWaited`: 0 = a holder that renews keeps the lock however long others wait. `maxHolders` ≥ 1: the
  /// leases held at once.
  explicit LockArbiter(Millis lease = kLockLease, Millis maxHoldWhileWaited = Millis{0}, int maxHolders = 1);

  /// Single dispatcher for a peer's message received at `now`. @p peer must not be kNoPeer.
  LockEvents handleMessage(PeerId peer, const LockMessage& message, Millis now);

  /// The peer's control connection closed: frees the lock at once if it held it, leaves the queue otherwise.
  LockEvents peerDisconnected(PeerId peer, Millis now);

  /// The host's user takes a lease back: `peer`'s (kNoPeer: every holder's) ends at once (Released{RevokedByHost} to
  /// all) and the queue's head is granted. Nothing when it holds none (not counted: this is no network input).
  LockEvents revokeByHost(Millis now, PeerId peer = kNoPeer);

  /// Revokes the holder if it has been silent for strictly more than the lease, or has held the lock too long while
  /// others wait (see the invariants). Call often (e.g. every 100 ms).
  LockEvents tick(Millis now);

  /// Checks a drag command; an accepted drag also counts as proof of life for the lease.
  DragVerdict acceptDrag(PeerId peer, LockEpoch epoch, Millis now);

  /// The holder of the oldest current lease (the only one when maxHolders is 1), kNoPeer when free.
  [[nodiscard]] PeerId holder() const { return m_holders.empty() ? kNoPeer : m_holders.front().peer; }
  /// Epoch of that lease, kNoEpoch when free.
  [[nodiscard]] LockEpoch epoch() const { return m_holders.empty() ? kNoEpoch : m_holders.front().epoch; }
  /// Every current lease, oldest grant first.
  [[nodiscard]] std::vector<LockHolding> holders() const;
  /// The epoch of `peer`'s lease, kNoEpoch when it holds none.
  [[nodiscard]] LockEpoch epochOf(PeerId peer) const;
  [[nodiscard]] int maxHolders() const { return m_maxHolders; }
  /// Waiting peers, head first.
  [[nodiscard]] const std::deque<PeerId>& queue() const { return m_queue; }
  /// Messages dropped as out of order or stale.
  [[nodiscard]] std::uint64_t ignoredMessages() const { return m_ignored; }
  /// Holders revoked for holding longer than maxHoldWhileWaited while others waited.
  [[nodiscard]] std::uint64_t revokedForWaiters() const { return m_revokedForWaiters; }
  /// When the first current lease runs out (revocation happens at the first tick strictly after it); nullopt when
  /// free.
  [[nodiscard]] std::optional<Millis> leaseDeadline() const;

 private:
  struct Holder {
    PeerId peer = kNoPeer;
    LockEpoch epoch = kNoEpoch;
    Millis lastHeard{0};
    Millis grantedAt{0};
  };

  LockEvents handleRequest(PeerId peer, Millis now);
  LockEvents handleRelease(PeerId peer, LockEpoch epoch, Millis now);
  LockEvents handleRenew(PeerId peer, LockEpoch epoch, Millis now);

  /// Ends `m_holders[index]`'s tenure with @p reason and grants the queue's head, if any.
  LockEvents endTenure(std::size_t index, LockReleaseReason reason, Millis now);
  [[nodiscard]] std::optional<std::size_t> indexOf(PeerId peer) const;
  /// Grants to @p peer with a fresh epoch; appends the broadcast to @p events.
  void grant(PeerId peer, Millis now, LockEvents& events);
  /// Removes @p peer from the queue; true if it was there.
  bool removeFromQueue(PeerId peer);
  [[nodiscard]] LockEvent queuedNotice(PeerId peer) const;
  LockEvents ignore();

  Millis m_lease;
  Millis m_maxHoldWhileWaited;
  Millis m_waitingSince{0};  ///< when the queue last became non-empty
  std::uint64_t m_revokedForWaiters = 0;
  int m_maxHolders = 1;
  std::vector<Holder> m_holders;  ///< oldest grant first
  std::deque<PeerId> m_queue;
  LockEpoch m_lastEpoch = kNoEpoch;
  std::uint64_t m_ignored = 0;
};

}  // namespace sc::session
