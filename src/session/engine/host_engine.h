#pragma once
// The rules of a session host without sockets (docs/protocol.md, "Sequence" and "Rules"), like ENet's protocol.c
// apart from unix.c: SessionHost (net/session_host.h) feeds it events with the session clock injected (`Micros
// now`) and carries out the HostActions it returns (host_engine_actions.h), arming ONE timer at wakeAt for tick().
//
// Behaviour:
//   - Admission: a connection attempt is admitted while fewer than maxPendingHandshakes connections are
//     unauthenticated (not welcomed, not closing) in all and fewer than maxPendingPerAddress from its address;
//     otherwise refused (connectionsOverLimit). Admitted ones get a peer id: the host's own user is peer 1
//     (kHostPeer), clients 2, 3, … (ids in use skipped, wrapping after 0xffff). Each pending connection whose
//     handshake has run strictly longer than handshakeTimeout at a housekeeping tick gets ExpireHandshake.
//   - After a Welcome: PeerList to everybody, the LevelList to the newcomer, PrefetchLevels, the current grant (if
//     any) to the newcomer. A ResolutionRequest picks a level (LevelLadder::pick); a built one starts a transfer at
//     once, otherwise RequestLevel and the transfer starts at onLevelReady() (which re-sends the LevelList to
//     everybody); a failed level falls back to the full model. When a transfer finishes: Keyframe{current frame, Z}
//     to that peer and PeerList to everybody.
//   - Lock: LockMessages go to the LockArbiter (ticked at every housekeeping tick, every 100 ms) and its events
//     are sent (to everybody or one peer); the host's own LockClient (peer 1) is driven in the same way.
//   - Constraints/Drag need arbiter.acceptDrag(peer, epoch); rejections are counted. Up to maxEditors peers hold a
//     lease at once, each with its own constraint set (shared_constraints.h); the deformer solves their union, each
//     holder's poses moving its own groups. A set that overlaps another holder's (its handles on their handles or
//     anchors, or its anchors on their handles), or makes the union too large, is refused: LockNotice{Refused} to
//     its sender, nothing changes. A lease's end takes its set out of the union. The union is factored off the
//     network thread (PrepareConstraints, then onConstraintsPrepared(), which installs it if the union has not
//     changed since); drag frames wait for that (the 1 s refresh does not), so the
//     network thread never runs the O(ids·m² + m³) factorisation. The host's own setConstraints() is synchronous. An
//     accepted drag solves at once and sends a frame (stamp = the drag's arrival) unless the previous DRAG frame went
//     out less than `coalesce` ago: then one frame with the latest pose when that spacing has passed. After a moving
//     frame, one still frame (StillFrameSchedule) unless another frame comes first; without drags the current Z is
//     repeated when idleRefresh has passed since the last frame (checked at housekeeping ticks). Every referenceEvery
//     frames each peer with a model gets a Keyframe.
//   - Presence (host_engine_presence.cpp): a member's is relayed to every other member with its id as author (never
//     echoed), at most presenceRate per peer (excess dropped and counted, no close), and reported to the host's own
//     user (PresenceReceived); the host's own (setLocalPresence) goes to every member with author kHostPeer.
//   - Heartbeat to every welcomed peer each second; a peer silent (onHeard) for more than peerTimeout is aborted.
//   - A message that is unexpected after the Welcome is counted (protocolErrors) and the connection closed.
//   - A hostile member (docs/security.md, "Hostile member"): a peer over messageRate is closed; LockRequest{Request},
//     ResolutionRequest and Constraints over their rates are counted (requestsThrottled) and dropped, except that the
//     latest ResolutionRequest / Constraints is kept and served at a housekeeping tick once the rate allows;
//     Constraints need unique ids < n and (ids · m²) ≤ maxConstraintWork. The adapter reports each peer's outgoing
//     queue (onSendQueue): over sendBudgetBytes, or not drained for sendStallTimeout, the peer is aborted and its lock
//     freed. The lock holder is revoked after maxLockHoldWhileWaited with others waiting.
//   - Seats are counted after the password proof (sessionFull(), asked by the handshake); pending connections have
//     their own limits and deadline, and when all pending slots are taken, the oldest pending connection of the most
//     represented address makes room for an address with fewer. Wrong passwords are logged and, after
//     freeWrongPasswords from one address, that address waits (doubling) before its next connection is admitted.
//   - shutdown(): Leave{HostEnded} to welcomed peers, Refused(ShuttingDown) to pending ones, every connection closed.
//   - Moderation (host_engine_moderation.cpp): kick() sends Leave{Kicked} to a member and closes it, its lock or
//     place in the queue freed at once; forceReleaseLock() revokes the holder (Released{RevokedByHost}). Whenever
//     the lock's queue changes, LockNotice{Waiting, queue} goes to everybody (a newcomer gets it after its Welcome),
//     so that the holder sees who waits.
// Network input never asserts (style.md item 6). Cost: O(peers) per event, plus a deformer solve per drag frame.
// Not thread-safe: one thread drives it.

#include "session/engine/constraint_work.h"
#include "session/engine/edit_history.h"
#include "session/engine/handshake_host.h"
#include "session/engine/host_engine_actions.h"
#include "session/engine/host_engine_options.h"
#include "session/engine/host_engine_peer.h"
#include "session/engine/host_engine_rate_limit.h"
#include "session/engine/host_model.h"
#include "session/engine/level_ladder.h"
#include "session/engine/lock_arbiter.h"
#include "session/engine/lock_client.h"
#include "session/engine/shared_constraints.h"
#include "session/engine/still_frame_schedule.h"
#include "spectral/spectral_deformer.h"

#include <array>
#include <chrono>
#include <cstdint>
#include <deque>
#include <map>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace sc::session {

/// The result of a connection attempt: the peer id offered in its Welcome, or kNoPeer (refused: abort it unread).
/// Seats are not decided here: the handshake asks sessionFull() after the password proof.
struct Admission {
  PeerId peer = kNoPeer;
  PeerId evict = kNoPeer;  ///< a pending connection of an over-represented address to abort to make room
};

class HostEngine {
 public:
  /// @param model          non-null, kept alive by the engine (the deformer refers into it).
  /// @param ladderTargets  the display levels' targets (LevelBuilder::targets(n)); empty: the full model only.
  HostEngine(std::shared_ptr<const HostModel> model, HostEngineOptions options,
             const std::vector<std::uint32_t>& ladderTargets);
  ~HostEngine();
  HostEngine(const HostEngine&) = delete;
  HostEngine& operator=(const HostEngine&) = delete;

  // === lifecycle
  /// Clamps the limits, starts the housekeeping and heartbeat cadences at `now`.
  HostActions start(Micros now);
  /// Leave to welcomed peers, Refused(ShuttingDown) to pending ones, all closed; nothing after. Idempotent.
  HostActions shutdown(Micros now);
  /// Runs what is due at `now` (coalesced frame, still frame, housekeeping, heartbeat).
  HostActions tick(Micros now);

  // === connections (events from the adapter)
  Admission onConnectionAttempt(const std::string& addressKey, Micros now);
  HostActions onWelcomed(PeerId peer, const QString& name, Micros now);
  HostActions onMessage(PeerId peer, const ControlMessage& message, Micros now);
  HostActions onDecodeError(PeerId peer, const QString& why, Micros now);
  /// The handshake refused the connection (it closes itself). A wrong password is logged with the address and
  /// counts towards that address's wait (freeWrongPasswords, wrongPasswordBackoff).
  HostActions onRefused(PeerId peer, RefuseReason reason, Micros now);
  /// The TLS handshake failed (the connection aborts itself).
  HostActions onTlsFailed(PeerId peer, const QString& why);
  void onOversizeMessage() { ++m_counters.oversizeMessages; }
  /// The connection is gone (closed by either side or aborted).
  HostActions onClosed(PeerId peer, Micros now);
  /// The last byte from `peer` arrived at `at`.
  void onHeard(PeerId peer, Micros at);
  /// The adapter's measure of `peer`'s outgoing queue (after its writes and at least every housekeeping period): a
  /// peer over sendBudgetBytes, or whose queue has not drained for sendStallTimeout, is aborted (its lock freed).
  HostActions onSendQueue(PeerId peer, const SendQueueReport& report, Micros now);
  HostActions onLevelReady(std::uint32_t target, const LevelFigures& figures, Micros now);
  HostActions onLevelFailed(std::uint32_t target, const QString& reason, Micros now);
  HostActions onTransferFinished(PeerId peer, Micros now);
  /// The worker's answer to PrepareConstraints{ticket}; nullopt: the set was invalid. A stale ticket is ignored.
  HostActions onConstraintsPrepared(std::uint64_t ticket, std::optional<spectral::PreparedConstraints> prepared,
                                    Micros now);

  // === the host's own user (peer 1)
  HostActions requestLock(Micros now, bool* sent = nullptr);
  HostActions releaseLock(Micros now, bool* sent = nullptr);
  HostActions setConstraints(const spectral::ConstraintSet& constraints, Micros now, bool* accepted = nullptr);
  HostActions drag(std::span<const spectral::HandleTransform> poses, Micros now, bool* accepted = nullptr);
  /// The host user's drag ended (as a member's StrokeEnd): what it changed becomes an edit step. Needs the lock.
  HostActions endStroke(Micros now, bool* accepted = nullptr);
  /// Undoes the latest applied step of ANYBODY (the host's own user moderates the shared history) or redoes the
  /// step the host's user undid last; `applied`: whether the shape changed. Needs no lock.
  HostActions edit(EditAction action, Micros now, bool* applied = nullptr);
  /// A saved session's shape and history, before anyone joined: the coefficients `Z` (m by 3, finite) become the
  /// current shape and the base of the constraints, and `steps` the history (oldest first). False (nothing
  /// changed) when `Z` or a step's delta has the wrong size or is not finite.
  bool restoreEdits(const Eigen::MatrixXd& Z, const std::vector<EditStep>& steps);
  /// The host's own user's presence: to every member with author kHostPeer (the caller paces it, PresenceSchedule).
  /// Nothing before start() or after shutdown(), or for a value that does not encode (non-finite, out of bounds).
  HostActions setLocalPresence(const Presence& presence, Micros now);

  // === moderation by the host's user (host_engine_moderation.cpp)
  /// Removes the member `peer` (not the host's own user): Leave{Kicked, text} to it, then a graceful close; its lock
  /// is freed and it leaves the queue at once, the PeerList goes out without it. `kicked`: whether it was a member.
  HostActions kick(PeerId peer, Micros now, const QString& text = {}, bool* kicked = nullptr);
  /// Takes `holder`'s lease back (kNoPeer: every lease; Released{RevokedByHost} to all; the queue's head is granted
  /// next). `revoked`: whether it held one.
  HostActions forceReleaseLock(Micros now, bool* revoked = nullptr, PeerId holder = kNoPeer);

  // === queries
  [[nodiscard]] PeerList peerList() const;
  [[nodiscard]] bool nameTaken(const QString& name) const;
  /// maxPeers members are welcomed: a newcomer's handshake refuses it (after its password proof).
  [[nodiscard]] bool sessionFull() const;
  [[nodiscard]] const LockArbiter& arbiter() const { return m_arbiter; }
  [[nodiscard]] const LockClient& localLock() const { return m_localLock; }
  [[nodiscard]] const HostEngineCounters& counters() const { return m_counters; }
  [[nodiscard]] std::optional<StatsReport> stats(PeerId peer) const;
  [[nodiscard]] std::uint32_t currentFrame() const { return m_frame; }
  [[nodiscard]] const Eigen::MatrixXd& coefficients() const { return *m_Z; }
  [[nodiscard]] const HostEngineOptions& options() const { return m_options; }
  /// For PrepareConstraints' worker: only its const prepare() may be called from another thread.
  [[nodiscard]] const spectral::SpectralDeformer& deformer() const { return *m_deformer; }
  /// A member's constraints are being factored (its drag frames wait).
  [[nodiscard]] bool constraintsInFlight() const { return m_constraintsInFlight.has_value(); }
  [[nodiscard]] const LevelLadder& ladder() const { return m_ladder; }
  /// The session's edit history (every committed stroke, by anyone).
  [[nodiscard]] const EditHistory& history() const { return m_history; }
  [[nodiscard]] bool isShutDown() const { return m_shutDown; }
  /// When tick() is next due: the earliest of the pending drag frame, the still frame, the next housekeeping and
  /// heartbeat; nullopt before start() and after shutdown(). What every HostActions::wakeAt holds.
  [[nodiscard]] std::optional<Micros> nextWakeUp() const;

 private:
  using Peer = HostEnginePeer;

  // host_engine.cpp: cadences
  void housekeeping(Micros now, HostActions& out);
  void heartbeat(Micros now, HostActions& out);
  /// Sets out.wakeAt = nextWakeUp().
  HostActions finish(HostActions out) const;
  [[nodiscard]] Peer* welcomed(PeerId id);
  void closePeer(Peer& peer, ClosePeer::How how, HostActions& out);
  // host_engine_peers.cpp: membership and transfers
  PeerId allocatePeerId();
  /// The oldest pending connection of the address with the most pending ones, if it has more than `fromAddress`
  /// + 1 (the newcomer's address would still have fewer); kNoPeer otherwise.
  PeerId evictionCandidate(int fromAddress) const;
  // host_engine_limits.cpp: the hostile-member limits
  /// False (and the peer closed, or the request counted and kept as the peer's deferred one) when `message` is over
  /// the peer's rates.
  bool withinRates(Peer& peer, const ControlMessage& message, Micros now, HostActions& out);
  /// At housekeeping: each member's deferred ResolutionRequest / Constraints, if its rate now allows.
  void serveDeferredRequests(Micros now, HostActions& out);
  bool constraintsWithinBounds(const Constraints& constraints) const;
  void wrongPassword(const Peer& peer, Micros now, HostActions& out);
  [[nodiscard]] bool addressWaiting(const std::string& address, Micros now) const;
  void forgetOldWrongPasswords(Micros now);
  void protocolFailure(Peer& peer, const QString& why, HostActions& out);
  void handleResolutionRequest(Peer& peer, const ResolutionRequest& request, HostActions& out);
  // host_engine_presence.cpp: presence relay
  /// A member's Presence within presenceRate: author set to its id, sent to every other member and reported
  /// (PresenceReceived); over the rate: dropped and counted.
  void relayPresence(Peer& peer, Presence presence, Micros now, HostActions& out);
  void startTransfer(Peer& peer, std::uint32_t target, HostActions& out);
  void levelReady(std::uint32_t target, HostActions& out);
  // host_engine_lock.cpp: lock, constraints, poses
  void dispatchLock(const LockEvents& events, Micros now, HostActions& out);
  /// The host's own LockClient's message (if any) to the arbiter; `sent`: whether there was one.
  HostActions localLockMessage(const std::optional<LockMessage>& message, Micros now, bool* sent);
  void handleConstraints(PeerId peer, const Constraints& constraints, Micros now, HostActions& out);
  /// False (LockNotice{Refused} to `peer`, counted) when `set` overlaps another holder's or the union would be over
  /// maxConstraintWork.
  bool admitConstraints(PeerId peer, LockEpoch epoch, const spectral::ConstraintSet& set, Micros now, HostActions& out);
  bool applyConstraints(PeerId peer, LockEpoch epoch, const spectral::ConstraintSet& set, Micros now, HostActions& out);
  bool acceptPose(PeerId peer, LockEpoch epoch, std::vector<spectral::HandleTransform> poses, Micros arrivedAt,
                  Micros now, HostActions& out);
  // host_engine_edits.cpp: strokes and the shared edit history
  /// Solves the pending poses if it can, splits the change since the deformer's base among the strokes going on
  /// (each holder's share) and folds each one's poses into it: the caller then moves the deformer's base to the
  /// current shape (rebase or install) and every stroke carries on from there with relative poses.
  void foldStrokes(Micros now, HostActions& out);
  /// foldStrokes(), the base moved to the current shape, then `author`'s stroke becomes an edit step of its author
  /// and ends (its next poses start from identity). kNoPeer: every stroke's change so far becomes a step, and the
  /// drags going on carry on. No step for a stroke without a change.
  void commitStroke(Micros now, HostActions& out, PeerId author = kNoPeer);
  /// The combined poses of every holder, relative to what is folded, laid out as the installed union's groups; each
  /// stroke's `solved` poses are set to what is returned for it.
  std::vector<spectral::HandleTransform> combinedPoses();
  /// `author` ended its stroke (StrokeEnd): commitStroke(), or, while its last poses wait for the union's
  /// factorisation, once they are solved.
  void endStrokeOf(PeerId author, Micros now, HostActions& out);
  /// `peer` holds no lease any more (released, revoked, gone): its stroke is a step, its set leaves the union.
  void endEditing(PeerId peer, Micros now, HostActions& out);
  /// Factors the current union off the network thread (PrepareConstraints); drags wait for it.
  void prepareUnion(HostActions& out);
  void applyEdit(PeerId requester, EditAction action, Micros now, HostActions& out);
  /// Sends the history's log to everybody and tells the adapter.
  void historyChanged(HostActions& out);
  [[nodiscard]] QString authorName(PeerId peer) const;
  // host_engine_moderation.cpp
  /// LockNotice{Waiting} to everybody (and the host's own LockClient) when the arbiter's queue differs from the one
  /// last announced; true when it did.
  bool announceLockQueue(Micros now, HostActions& out);
  [[nodiscard]] LockNotice waitingNotice() const;
  // host_engine_frames.cpp: frames
  /// Sends the current Z as a frame, solving the pending pose first if there is one. `jumped`: Z changed outside
  /// a drag (undo / redo), which counts as a moving frame for the still frame.
  void produceFrame(Micros now, bool still, HostActions& out, bool jumped = false);
  void produceStillFrame(Micros now, HostActions& out);
  void sendKeyframe(PeerId peer, HostActions& out);

  std::shared_ptr<const HostModel> m_model;
  HostEngineOptions m_options;
  LevelLadder m_ladder;
  std::map<PeerId, Peer> m_peers;  ///< every open connection, welcomed or not
  LockArbiter m_arbiter;
  LockClient m_localLock{kHostPeer};
  std::deque<PeerId> m_announcedQueue;  ///< the lock queue as last sent in a Waiting notice
  std::unique_ptr<spectral::SpectralDeformer> m_deformer;
  HostEngineCounters m_counters;
  PeerId m_nextPeerId = kHostPeer + 1;
  std::uint32_t m_transferId = 0;
  std::uint32_t m_heartbeatSequence = 0;
  bool m_started = false;
  bool m_shutDown = false;
  Micros m_nextHousekeeping{0};
  Micros m_nextHeartbeat{0};
  struct WrongPasswords {
    int count = 0;
    Micros last{0};
    Micros notBefore{0};  ///< no connection from the address is admitted before this
  };
  std::map<std::string, WrongPasswords> m_wrongPasswords;  ///< by admission key, at most kMaxTrackedAddresses

  // frames
  std::shared_ptr<const Eigen::MatrixXd> m_Z;
  std::uint32_t m_frame = 0;
  int m_framesSinceKeyframe = 0;
  Micros m_lastFrameAt{0};
  Micros m_lastDragFrameAt{0};  ///< the coalescing spacing counts from drag frames only
  /// One holder's drag going on. Poses are its own groups', as it sends them (from its stroke's start); what the
  /// deformer gets is relative to `folded`, the poses already in the deformer's base.
  struct Stroke {
    std::vector<spectral::HandleTransform> received;  ///< the latest poses it sent
    std::vector<spectral::HandleTransform> solved;    ///< `received` as of the last solve
    std::vector<spectral::HandleTransform> folded;    ///< in the base since the last rebase (empty: none)
    Eigen::MatrixXd share;                            ///< its change folded so far (empty: none)
    bool unsolved = false;                            ///< `received` came after the last solve
    bool ending = false;  ///< its StrokeEnd came while its poses waited for a factorisation: ends after it
  };
  std::map<PeerId, Stroke> m_strokes;  ///< by author
  SharedConstraints m_shared;          ///< every holder's latest accepted set
  SharedConstraints m_installed;       ///< what the deformer has (m_shared once a preparation is installed)
  EditHistory m_history;
  std::optional<Micros> m_pendingArrival;  ///< set while an accepted drag waits for its frame
  std::optional<Micros> m_coalesceDue;     ///< when the pending pose's frame goes out
  std::optional<Micros> m_stillDue;        ///< when the still frame goes out
  struct ConstraintsInFlight {
    std::uint64_t ticket = 0;
    std::uint64_t version = 0;  ///< installed only while m_shared.version() is still this
  };
  std::optional<ConstraintsInFlight> m_constraintsInFlight;
  std::uint64_t m_constraintsTicket = 0;
  StillFrameSchedule m_stillSchedule;
};

}  // namespace sc::session
