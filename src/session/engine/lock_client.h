#pragma once
// Peer side of the edit-lock protocol: what this peer asked for, what the host told it, who holds the lock (for
// the UI) and when to send a renew. A pure state machine over LockNotices and an injected monotonic clock; every
// method that must reach the host returns the LockMessage to send (nullopt: send nothing).
//
// States and transitions (one changeState() performs the entry side effects):
//
//   Idle --request()--> Requested --Queued--> Queued --Granted(self)--> Held --release()--> Releasing
//                           \---------Granted(self)-------------------/   |                    |
//   Held --Released(self) (lease expired, disconnected)--> Idle           |        Released(self) | Dequeued
//   Requested | Queued --release()--> Releasing  (cancel; sends Release{kNoEpoch})               v
//   Held --Granted(other)--> Held (several peers may hold a lease at once, since version 5)     Idle
//   any --Waiting{queue}--> same state: waiting() is the host's queue (a Queued peer's position follows it)
//
// Invariants: heldEpoch() != kNoEpoch exactly in Held; canDrag() only in Held; holders() mirror the host's Granted
// and Released broadcasts whatever this peer's own state. A Refused notice for our held epoch (our constraints
// overlap another holder's) leaves the state as it is and is kept in lastRefusal() for the UI. Notices that make no
// sense in the current state are ignored and counted (ignoredNotices()), except a Granted(self) while Idle, which is
// answered with a Release so the host does not keep a lock nobody uses.
//
// Cost: O(1) per call.

#include <optional>
#include <vector>

#include "session/wire/lock_messages.h"

namespace sc::session {

/// The host refused this peer's constraints (LockNotice Refused): `holders` are those whose handles or anchors they
/// overlap; empty: everybody's together would be too many. `serial` counts refusals (1 = the first).
struct LockRefusal {
  std::uint64_t serial = 0;
  std::vector<PeerId> holders;
  friend bool operator==(const LockRefusal&, const LockRefusal&) = default;
};

enum class LockState : std::uint8_t { Idle, Requested, Queued, Held, Releasing };

class LockClient {
 public:
  explicit LockClient(PeerId self, Millis renewEvery = kLockRenewEvery);

  /// Asks for the lock. From Idle only; elsewhere nullopt (already asked, holding or releasing).
  std::optional<LockMessage> request(Millis now);
  /// Gives the lock back (Held) or cancels the request (Requested, Queued); nullopt from Idle or Releasing.
  std::optional<LockMessage> release(Millis now);
  /// Applies one host notice; returns a reply when one is due (only a Release for an unwanted grant).
  std::optional<LockMessage> apply(const LockNotice& notice, Millis now);
  /// In Held, returns a Renew when at least renewEvery has passed since the grant or the last renew.
  std::optional<LockMessage> pollRenew(Millis now);

  [[nodiscard]] LockState state() const { return m_state; }
  [[nodiscard]] PeerId self() const { return m_self; }
  [[nodiscard]] bool canDrag() const { return m_state == LockState::Held; }
  /// Epoch to stamp on drags; kNoEpoch unless Held.
  [[nodiscard]] LockEpoch heldEpoch() const { return m_heldEpoch; }
  /// Who holds a lease as far as this peer knows, oldest grant first, for the UI.
  [[nodiscard]] std::vector<PeerId> holders() const;
  /// The oldest of them (kNoPeer: nobody), and the epoch of the latest grant seen (kept after a release, so that
  /// older grants arriving late are recognised and ignored).
  [[nodiscard]] PeerId holder() const { return m_holders.empty() ? kNoPeer : m_holders.front().peer; }
  [[nodiscard]] LockEpoch holderEpoch() const { return m_holderEpoch; }
  /// 1 = next in line; 0 unless Queued.
  [[nodiscard]] std::uint32_t queuePosition() const { return m_queuePosition; }
  /// The peers waiting for the lock, head first, as the host last broadcast them (Waiting notices; ≤ kMaxPeers).
  [[nodiscard]] const std::vector<PeerId>& waiting() const { return m_waiting; }
  /// Why this peer last stopped holding (Released = it gave the lock back itself); nullopt before any tenure ended
  /// and again from its next request().
  [[nodiscard]] std::optional<LockReleaseReason> lastLoss() const { return m_lastLoss; }
  /// When pollRenew() will next return a Renew; nullopt unless Held. Lets the adapter arm a single timer.
  [[nodiscard]] std::optional<Millis> nextRenewDue() const;
  [[nodiscard]] std::uint64_t ignoredNotices() const { return m_ignored; }
  /// The host's latest refusal of this peer's constraints; nullopt before any.
  [[nodiscard]] const std::optional<LockRefusal>& lastRefusal() const { return m_refusal; }

 private:
  /// The only place m_state changes. Entry effects: Held records @p heldEpoch and stamps the renew clock; every
  /// other state clears the held epoch; every state but Queued clears the queue position.
  void changeState(LockState next, Millis now, LockEpoch heldEpoch = kNoEpoch);

  std::optional<LockMessage> onGranted(const LockNotice& notice, Millis now);
  void onQueued(const LockNotice& notice, Millis now);
  void onReleased(const LockNotice& notice, Millis now);
  void onDequeued(Millis now);
  void onWaiting(const LockNotice& notice);
  void onRefused(const LockNotice& notice);
  void forgetHolder(PeerId peer);
  std::optional<LockMessage> ignore();

  PeerId m_self;
  Millis m_renewEvery;
  LockState m_state = LockState::Idle;
  std::vector<LockHolding> m_holders;  ///< oldest grant first
  std::optional<LockRefusal> m_refusal;
  std::uint64_t m_refusalCount = 0;
  LockEpoch m_holderEpoch = kNoEpoch;
  LockEpoch m_heldEpoch = kNoEpoch;
  std::uint32_t m_queuePosition = 0;
  Millis m_lastRenew{0};
  std::optional<LockReleaseReason> m_lastLoss;
  std::vector<PeerId> m_waiting;
  std::uint64_t m_ignored = 0;
};

}  // namespace sc::session
