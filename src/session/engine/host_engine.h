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
//   - Constraints/Drag need arbiter.acceptDrag(peer, epoch); rejections are counted. An accepted drag solves at
//     once and sends a frame (stamp = the drag's arrival) unless the previous DRAG frame went out less than
//     `coalesce` ago: then one frame with the latest pose when that spacing has passed. After a moving frame, one
//     still frame (StillFrameSchedule) unless another frame comes first; without drags the current Z is repeated
//     when idleRefresh has passed since the last frame (checked at housekeeping ticks). Every referenceEvery frames
//     each peer with a model gets a Keyframe.
//   - Heartbeat to every welcomed peer each second; a peer silent (onHeard) for more than peerTimeout is aborted.
//   - A message that is unexpected after the Welcome is counted (protocolErrors) and the connection closed.
//   - shutdown(): Leave to welcomed peers, Refused(ShuttingDown) to pending ones, every connection closed.
// Network input never asserts (style.md item 6). Cost: O(peers) per event, plus a deformer solve per drag frame.
// Not thread-safe: one thread drives it.

#include "session/engine/handshake_host.h"
#include "session/engine/host_engine_actions.h"
#include "session/engine/host_engine_peer.h"
#include "session/engine/host_model.h"
#include "session/engine/level_ladder.h"
#include "session/engine/lock_arbiter.h"
#include "session/engine/lock_client.h"
#include "session/engine/still_frame_schedule.h"
#include "spectral/spectral_deformer.h"

#include <array>
#include <chrono>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace sc::session {

inline constexpr PeerId kHostPeer = 1;                 ///< the host's own user
inline constexpr Micros kHousekeepingPeriod{100'000};  ///< handshake deadlines, lock lease, own renew, idle refresh
inline constexpr Micros kHeartbeatPeriod{1'000'000};

/// A clock reading in whole milliseconds (what the lock arbiter, the handshakes and lastHeard count in).
inline Millis toMillis(Micros t) { return std::chrono::duration_cast<Millis>(t); }

/// The host's rules (SessionHostOptions derives from it and adds the sockets' settings).
struct HostEngineOptions {
  QString hostName = QStringLiteral("host");  ///< the host's own PeerList entry (peer 1)
  int maxPeers = 16;  ///< clients at once, 1..kMaxPeers − 1 (the PeerList also holds the host)
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
};

/// What the host rejected or dropped, for tests and the UI.
struct HostEngineCounters {
  std::array<std::uint64_t, kRefuseReasonLast + 1> refusals{};  ///< indexed by RefuseReason's wire value
  std::uint64_t protocolErrors = 0;  ///< decode errors or unexpected messages after the Welcome (connection closed)
  std::uint64_t dragsAccepted = 0;
  std::uint64_t dragsNotHolder = 0;
  std::uint64_t dragsStale = 0;
  std::uint64_t constraintsAccepted = 0;
  std::uint64_t constraintsRejected = 0;  ///< lock verdict, or ids ≥ n / empty groups
  std::uint64_t silentPeersDropped = 0;
  std::uint64_t framesSent = 0;
  std::uint64_t keyframesSent = 0;
  std::uint64_t stillFramesSent = 0;  ///< still frames (included in framesSent), see StillFrameSchedule
  std::uint64_t transfersCompleted = 0;
  std::uint64_t tlsFailures = 0;           ///< TLS handshakes that failed (e.g. a client not speaking TLS)
  std::uint64_t connectionsOverLimit = 0;  ///< aborted at accept: too many unauthenticated connections
  std::uint64_t oversizeMessages = 0;      ///< control frames longer than kMaxControlMessageSize (closed)

  [[nodiscard]] std::uint64_t refusalsFor(RefuseReason reason) const {
    return refusals[static_cast<std::size_t>(reason)];
  }
};

/// The result of a connection attempt: the peer id offered in its Welcome, or kNoPeer (refused: abort it unread).
struct Admission {
  PeerId peer = kNoPeer;
  bool sessionFull = false;  ///< maxPeers connections already open: the handshake refuses it (SessionFull)
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
  /// The handshake refused the connection (it closes itself).
  void onRefused(PeerId peer, RefuseReason reason);
  /// The TLS handshake failed (the connection aborts itself).
  HostActions onTlsFailed(PeerId peer, const QString& why);
  void onOversizeMessage() { ++m_counters.oversizeMessages; }
  /// The connection is gone (closed by either side or aborted).
  HostActions onClosed(PeerId peer, Micros now);
  /// The last byte from `peer` arrived at `at`.
  void onHeard(PeerId peer, Micros at);
  HostActions onLevelReady(std::uint32_t target, const LevelFigures& figures, Micros now);
  HostActions onLevelFailed(std::uint32_t target, const QString& reason, Micros now);
  HostActions onTransferFinished(PeerId peer, Micros now);

  // === the host's own user (peer 1)
  HostActions requestLock(Micros now, bool* sent = nullptr);
  HostActions releaseLock(Micros now, bool* sent = nullptr);
  HostActions setConstraints(const spectral::ConstraintSet& constraints, Micros now, bool* accepted = nullptr);
  HostActions drag(std::span<const spectral::HandleTransform> poses, Micros now, bool* accepted = nullptr);

  // === queries
  [[nodiscard]] PeerList peerList() const;
  [[nodiscard]] bool nameTaken(const QString& name) const;
  [[nodiscard]] const LockArbiter& arbiter() const { return m_arbiter; }
  [[nodiscard]] const LockClient& localLock() const { return m_localLock; }
  [[nodiscard]] const HostEngineCounters& counters() const { return m_counters; }
  [[nodiscard]] std::optional<StatsReport> stats(PeerId peer) const;
  [[nodiscard]] std::uint32_t currentFrame() const { return m_frame; }
  [[nodiscard]] const Eigen::MatrixXd& coefficients() const { return *m_Z; }
  [[nodiscard]] const HostEngineOptions& options() const { return m_options; }
  [[nodiscard]] const LevelLadder& ladder() const { return m_ladder; }
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
  void protocolFailure(Peer& peer, const QString& why, HostActions& out);
  void handleResolutionRequest(Peer& peer, const ResolutionRequest& request, HostActions& out);
  void startTransfer(Peer& peer, std::uint32_t target, HostActions& out);
  void levelReady(std::uint32_t target, HostActions& out);
  // host_engine_lock.cpp: lock, constraints, poses
  void dispatchLock(const LockEvents& events, Micros now, HostActions& out);
  /// The host's own LockClient's message (if any) to the arbiter; `sent`: whether there was one.
  HostActions localLockMessage(const std::optional<LockMessage>& message, Micros now, bool* sent);
  void handleConstraints(PeerId peer, const Constraints& constraints, Micros now);
  bool applyConstraints(PeerId peer, LockEpoch epoch, const spectral::ConstraintSet& set, Micros now);
  bool acceptPose(PeerId peer, LockEpoch epoch, std::vector<spectral::HandleTransform> poses, Micros arrivedAt,
                  Micros now, HostActions& out);
  // host_engine_frames.cpp: frames
  void produceFrame(Micros now, bool still, HostActions& out);
  void produceStillFrame(Micros now, HostActions& out);
  void sendKeyframe(PeerId peer, HostActions& out);

  std::shared_ptr<const HostModel> m_model;
  HostEngineOptions m_options;
  LevelLadder m_ladder;
  std::map<PeerId, Peer> m_peers;  ///< every open connection, welcomed or not
  LockArbiter m_arbiter;
  LockClient m_localLock{kHostPeer};
  std::unique_ptr<spectral::SpectralDeformer> m_deformer;
  HostEngineCounters m_counters;
  PeerId m_nextPeerId = kHostPeer + 1;
  std::uint32_t m_transferId = 0;
  std::uint32_t m_heartbeatSequence = 0;
  bool m_started = false;
  bool m_shutDown = false;
  Micros m_nextHousekeeping{0};
  Micros m_nextHeartbeat{0};

  // frames
  std::shared_ptr<const Eigen::MatrixXd> m_Z;
  std::uint32_t m_frame = 0;
  int m_framesSinceKeyframe = 0;
  Micros m_lastFrameAt{0};
  Micros m_lastDragFrameAt{0};  ///< the coalescing spacing counts from drag frames only
  std::vector<spectral::HandleTransform> m_pendingPoses;
  std::optional<Micros> m_pendingArrival;  ///< set while an accepted drag waits for its frame
  std::optional<Micros> m_coalesceDue;     ///< when the pending pose's frame goes out
  std::optional<Micros> m_stillDue;        ///< when the still frame goes out
  StillFrameSchedule m_stillSchedule;
};

}  // namespace sc::session
