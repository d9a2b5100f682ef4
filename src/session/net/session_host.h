#pragma once
// The host of a session over real sockets (docs/protocol.md, "Sequence" and "Rules"): a TlsServer for the control
// connections (TLS 1.3 with the host's certificate, docs/security.md; one HostPeerConnection each: handshake, then
// session messages), a HostDatagramChannel for the
// coefficient frames, the LockArbiter, the SpectralDeformer and the LevelLibrary. A thin adapter: the protocol
// decisions are the pure state machines'; this class wires them to sockets, timers and the deformer.
//
// Behaviour (all on the thread that owns the host):
//   - Peer ids: the host's own user is peer 1 (kHostPeer); clients get 2, 3, … (ids in use are skipped).
//   - After a Welcome: PeerList to everybody, the current grant (if any) to the newcomer. A ResolutionRequest
//     starts a model transfer of LevelLibrary::pick(wanted) (built, encoded and hashed off-thread once, when first
//     asked for; a transfer reuses the cached payload and SHA-256); when its last chunk is queued the peer gets
//     Keyframe{current frame, Z} and everybody a PeerList with its new level.
//   - Lock: LockMessages go to the arbiter (ticked every 100 ms); its events are sent (broadcast or to one peer).
//   - Constraints/Drag need arbiter.acceptDrag(peer, epoch); a rejected one is counted (NotHolder / StaleEpoch /
//     bad vertex ids). An accepted drag solves at once and sends a frame (timestamp = the drag's arrival), unless
//     the previous frame went out less than `coalesce` ago: then one single-shot timer sends the latest pose.
//     When no frame follows a moving frame within about one frame interval (StillFrameSchedule: 1.25 × the
//     measured interval, clamped to 20–100 ms), one "still" frame repeats Z under a new frame number, so that
//     extrapolating clients see zero velocity (still_frame_schedule.h; off with `stillFrame` = false).
//     Without drags the current Z is repeated every `idleRefresh` after the last frame (the still frame
//     included). Every `referenceEvery` frames (still and refresh frames count) each peer that has a model gets
//     a Keyframe (exact reference for its Hausdorff measurement).
//   - Heartbeat to every peer each second; a peer silent (no byte) for `peerTimeout` is dropped. Leave or a closed
//     socket: the arbiter frees or dequeues the peer, the datagram channel forgets it, PeerList to everybody.
//   - A decode error or an unexpected message after the Welcome is counted and the connection closed.
//   - Limits on unauthenticated connections (not yet welcomed, TLS handshake included): at most
//     maxPendingHandshakes in all and maxPendingPerAddress from one address; a connection over a limit is aborted
//     at accept, before any byte is read or sent (counted in connectionsOverLimit). Each must be welcomed within
//     handshakeTimeout (10 s) of its accept, TLS handshake included, or it is closed.
//   - shutdown() sends Leave to every peer and stops listening.
// Network input never asserts (style.md item 6); every rejection is counted in counters().

#include "session/wire/coefficient_codec.h"
#include "session/wire/control_messages.h"
#include "session/engine/handshake_host.h"
#include "session/engine/host_model.h"
#include "session/engine/lock_arbiter.h"
#include "session/engine/lock_client.h"
#include "session/engine/receiver_statistics.h"
#include "session/engine/still_frame_schedule.h"
#include "session/net/tls_identity.h"
#include "spectral/spectral_deformer.h"

#include <Eigen/Core>
#include <QtCore/QObject>
#include <QtCore/QString>
#include <QtNetwork/QHostAddress>

#include <array>
#include <chrono>
#include <cstdint>
#include <deque>
#include <map>
#include <memory>
#include <optional>
#include <span>
#include <vector>

class QTimer;

namespace sc::session {

class HostDatagramChannel;
class HostPeerConnection;
class LevelLibrary;
class TlsServer;

inline constexpr PeerId kHostPeer = 1;  ///< the host's own user

struct SessionHostOptions {
  QHostAddress address = QHostAddress::Any;                   ///< TCP and UDP bind address
  quint16 tcpPort = 0;                                        ///< 0 = any free port (see SessionHost::tcpPort())
  quint16 udpPort = 0;                                        ///< 0 = any free port
  std::optional<QString> password;                            ///< none: open session (no Challenge)
  std::uint32_t pbkdf2Iterations = kDefaultPbkdf2Iterations;  ///< 1..kMaxPbkdf2Iterations
  QString hostName = QStringLiteral("host");                  ///< the host's own PeerList entry (peer 1)
  int maxPeers = 16;  ///< clients at once, 1..kMaxPeers − 1 (the PeerList also holds the host)
  spectral::DeformerOptions deformer;
  CodecOptions codec;       ///< datagram layout (parts, protected rows, band size)
  int referenceEvery = 15;  ///< a Keyframe to every loaded peer each this many frames; 1 = every frame; 0 = never
  std::chrono::milliseconds idleRefresh{1000};   ///< repeat the current Z when nothing moved for this long
  std::chrono::milliseconds coalesce{8};         ///< minimum spacing of drag frames
  std::chrono::milliseconds peerTimeout{10000};  ///< a peer silent this long is dropped
  /// One still frame after the last moving frame (still_frame_schedule.h); false: none (e.g. a test emulating the
  /// loss of the still frame).
  bool stillFrame = true;
  /// The TLS certificate and key. None: loadOrCreateTlsIdentity(defaultTlsIdentityDirectory()) at start() (the
  /// same fingerprint every run), or a fresh in-memory one when that folder cannot be used (logged).
  std::shared_ptr<const TlsIdentity> identity;
  int maxPendingHandshakes = 16;  ///< unauthenticated connections at once, ≥ 1
  int maxPendingPerAddress = 8;   ///< unauthenticated connections at once from one IP address, ≥ 1
  std::chrono::milliseconds handshakeTimeout = kHandshakeTimeout;  ///< TLS + Hello + password proof, from accept
};

/// What the host rejected or dropped, for tests and the UI.
struct SessionHostCounters {
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

class SessionHost final : public QObject {
  Q_OBJECT
  Q_DISABLE_COPY_MOVE(SessionHost)

 public:
  /// @param model  non-null; 1 ≤ m ≤ kMaxRows, #V ≥ 3. Kept alive as long as the host (the deformer refers to it).
  SessionHost(std::shared_ptr<const HostModel> model, SessionHostOptions options, QObject* parent = nullptr);
  ~SessionHost() override;

  /// Loads or creates the TLS identity (options.identity), derives the password secret (PBKDF2, once), binds UDP,
  /// then listens on TCP. False with `error` set on failure.
  bool start(QString* error = nullptr);
  /// Sends Leave to every peer, closes every connection and stops listening. Idempotent. The Leaves are written
  /// by the event loop: keep the host alive (and the loop running) briefly after shutdown(); destroying a host
  /// without it just drops every connection.
  void shutdown();

  [[nodiscard]] quint16 tcpPort() const;
  [[nodiscard]] quint16 udpPort() const;
  /// SHA-256 of the host's TLS certificate (kFingerprintSize bytes; empty before start()): what users compare
  /// (formatFingerprint()) and clients pin.
  [[nodiscard]] QByteArray fingerprint() const { return m_identity ? m_identity->fingerprint() : QByteArray(); }
  [[nodiscard]] const SessionHostOptions& options() const { return m_options; }

  /// The current PeerList (the host first).
  [[nodiscard]] PeerList peerList() const;
  [[nodiscard]] PeerId lockHolder() const;
  [[nodiscard]] LockEpoch lockEpoch() const;
  [[nodiscard]] const std::deque<PeerId>& lockQueue() const;
  [[nodiscard]] const SessionHostCounters& counters() const { return m_counters; }
  /// A peer's latest StatsReport; nullopt before its first (or for an unknown peer).
  [[nodiscard]] std::optional<StatsReport> stats(PeerId peer) const;
  /// Frame number of the latest frame sent (0 before the first) and its Z (m by 3).
  [[nodiscard]] std::uint32_t currentFrame() const { return m_frame; }
  [[nodiscard]] const Eigen::MatrixXd& coefficients() const { return m_Z; }
  [[nodiscard]] HostDatagramChannel& channel() { return *m_channel; }
  [[nodiscard]] LevelLibrary& levels() { return *m_levels; }

  // --- the host's own user (peer 1), e.g. the desktop app dragging on the host
  /// Asks for the lock (false when already asked for or held).
  bool requestLock();
  /// Releases (or cancels the request for) the lock.
  bool releaseLock();
  [[nodiscard]] const LockClient& localLock() const { return m_localLock; }
  /// Sets the constraints as the lock holder; false without the lock or with invalid ids.
  bool setConstraints(const spectral::ConstraintSet& constraints);
  /// Drags as the lock holder (one pose per handle group); false without the lock.
  bool drag(std::span<const spectral::HandleTransform> poses);

 signals:
  void peersChanged();
  void lockChanged();
  void frameSent(std::uint32_t frame);
  void statsReported(sc::session::PeerId peer, const sc::session::StatsReport& report);
  void logMessage(const QString& message);

 private:
  struct Peer;

  void acceptConnections();
  bool resolveIdentity(QString* error);
  /// True when one more unauthenticated connection from `address` stays within the limits.
  [[nodiscard]] bool admits(const QHostAddress& address) const;
  void onWelcomed(HostPeerConnection* connection);
  void onMessage(HostPeerConnection* connection, const ControlMessage& message);
  void onClosed(HostPeerConnection* connection);
  void onTransferFinished(HostPeerConnection* connection);
  void onLevelReady(std::uint32_t target);
  void onLevelFailed(std::uint32_t target, const QString& reason);
  void protocolFailure(HostPeerConnection* connection, const QString& why);

  void handleResolutionRequest(Peer& peer, const ResolutionRequest& request);
  void handleConstraints(PeerId peer, const Constraints& constraints);
  void handleDrag(PeerId peer, const Drag& drag, Micros arrivedAt);
  void startTransfer(Peer& peer, std::uint32_t target);
  bool applyConstraints(PeerId peer, LockEpoch epoch, const spectral::ConstraintSet& set);
  bool acceptPose(PeerId peer, LockEpoch epoch, std::vector<spectral::HandleTransform> poses, Micros arrivedAt);

  void dispatchLock(const LockEvents& events);
  void broadcast(const ControlMessage& message);
  void broadcastPeerList();
  void sendKeyframe(HostPeerConnection& connection);
  void produceFrame();
  void produceStillFrame();  ///< the still frame timer: a frame with the same Z unless a frame is pending
  void housekeeping();       ///< every 100 ms: handshake timeouts, lock lease, own renew, idle refresh
  void heartbeat();          ///< every second: Heartbeat to each peer, silent peers dropped
  PeerId allocatePeerId();
  [[nodiscard]] Millis now() const;

  std::shared_ptr<const HostModel> m_model;
  SessionHostOptions m_options;
  std::optional<SessionSecret> m_secret;
  std::shared_ptr<const TlsIdentity> m_identity;
  TlsServer* m_server = nullptr;
  HostDatagramChannel* m_channel = nullptr;
  LevelLibrary* m_levels = nullptr;
  QTimer* m_housekeeping = nullptr;
  QTimer* m_heartbeat = nullptr;
  QTimer* m_coalesce = nullptr;
  QTimer* m_still = nullptr;                        ///< single-shot: the still frame after the last moving frame
  std::map<PeerId, std::unique_ptr<Peer>> m_peers;  ///< every open connection, welcomed or not
  LockArbiter m_arbiter;
  LockClient m_localLock{kHostPeer};
  std::unique_ptr<spectral::SpectralDeformer> m_deformer;
  SessionHostCounters m_counters;
  PeerId m_nextPeerId = kHostPeer + 1;
  std::uint32_t m_transferId = 0;
  std::uint32_t m_heartbeatSequence = 0;

  // frames
  Eigen::MatrixXd m_Z;
  std::uint32_t m_frame = 0;
  int m_framesSinceKeyframe = 0;
  Micros m_lastFrameAt{0};
  Micros m_lastDragFrameAt{0};  ///< last frame made from a drag: the coalescing spacing counts from it only, so a
                                ///< still or idle frame never delays the next drag's frame
  std::vector<spectral::HandleTransform> m_pendingPoses;
  std::optional<Micros> m_pendingArrival;  ///< set while an accepted drag waits for its frame
  StillFrameSchedule m_stillSchedule;
  bool m_started = false;
  bool m_shutDown = false;
};

}  // namespace sc::session
