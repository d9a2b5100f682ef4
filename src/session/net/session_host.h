#pragma once
// The host of a session over real sockets: a thin adapter over HostEngine (engine/host_engine.h), which holds every
// session rule (admission, membership, transfers scheduling, lock dispatch, drag coalescing, still, idle and key
// frames, heartbeats and timeouts; see its header for the behaviour). This class owns only what the engine must
// not: a TlsServer for the control connections (TLS 1.3 with the host's certificate, docs/security.md; one
// HostPeerConnection each: handshake, then session messages), a HostDatagramChannel for the coefficient frames,
// the LevelLibrary (the level-building thread; its builder is SessionHostOptions::levelBuilder) and ONE timer armed
// at the engine's next wake-up. It translates socket events into engine events (with sessionNow()) and carries
// out the HostActions the engine returns, in order; it emits its signals when the engine says so.
//
//   - start() resolves the TLS identity, derives the password secret, binds UDP and listens on TCP, and has the
//     LevelLibrary build the smallest level at once (a progressive join's preview waits for no decimation).
//   - A connection over the engine's admission limits is aborted at accept, before any byte is read or sent; a
//     pending connection the engine evicts to make room is aborted.
//   - After carrying out the engine's actions (and at every timer) it reports each connection's outgoing queue to
//     the engine (HostEngine::onSendQueue); each connection refuses writes over the engine's send budget.
//   - A member's Constraints are factored on a worker thread (m_solver, one thread), so the network thread never
//     runs the O(ids·m² + m³) refactorisation; the destructor waits for a running one.
//   - shutdown() sends Leave to every peer and stops listening.
// Network input never asserts (style.md item 6); every rejection is counted in counters().

#include "session/engine/handshake_host.h"
#include "session/engine/host_engine.h"
#include "session/engine/host_model.h"
#include "session/engine/level_builder.h"
#include "session/engine/lock_arbiter.h"
#include "session/engine/lock_client.h"
#include "session/engine/receiver_statistics.h"
#include "session/net/tls_identity.h"
#include "session/wire/coefficient_codec.h"
#include "session/wire/control_messages.h"
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

class QThreadPool;
class QTimer;

namespace sc::session {

class HostDatagramChannel;
class HostPeerConnection;
class LevelLibrary;
class TlsServer;

/// The host's settings: the engine's rules (HostEngineOptions: host name, limits, cadences, deformer) plus the
/// sockets', the codec's and the level builder's.
struct SessionHostOptions : HostEngineOptions {
  QHostAddress address = QHostAddress::Any;  ///< TCP and UDP bind address
  quint16 tcpPort = 0;                       ///< 0 = any free port (see SessionHost::tcpPort())
  quint16 udpPort = 0;                       ///< 0 = any free port
  std::optional<QString> password;           ///< none: open session (no Challenge); start() keeps only the derived key
  std::uint32_t pbkdf2Iterations = kDefaultPbkdf2Iterations;  ///< 1..kMaxPbkdf2Iterations
  CodecOptions codec;                                         ///< datagram layout (parts, protected rows, band size)
  /// The TLS certificate and key. None: loadOrCreateTlsIdentity(defaultTlsIdentityDirectory()) at start() (the
  /// same fingerprint every run), or a fresh in-memory one when that folder cannot be used (logged).
  std::shared_ptr<const TlsIdentity> identity;
  /// Builds the display levels (e.g. {model::levelTargetList, model::decimatedLevel}); empty: the full model only.
  LevelBuilder levelBuilder;
};

/// What the host rejected or dropped, for tests and the UI.
using SessionHostCounters = HostEngineCounters;

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
  /// The TLS identity in use (null before start()): the relay signs its messages with its key.
  [[nodiscard]] std::shared_ptr<const TlsIdentity> identity() const { return m_identity; }
  /// The model this host serves (its m and vertex count are the session's facts).
  [[nodiscard]] const HostModel& model() const { return *m_model; }

  /// The current PeerList (the host first).
  [[nodiscard]] PeerList peerList() const { return m_engine.peerList(); }
  [[nodiscard]] PeerId lockHolder() const { return m_engine.arbiter().holder(); }
  /// Every current lease, oldest grant first (up to options().maxEditors at once).
  [[nodiscard]] std::vector<LockHolding> lockHolders() const { return m_engine.arbiter().holders(); }
  [[nodiscard]] LockEpoch lockEpoch() const { return m_engine.arbiter().epoch(); }
  [[nodiscard]] const std::deque<PeerId>& lockQueue() const { return m_engine.arbiter().queue(); }
  [[nodiscard]] const SessionHostCounters& counters() const { return m_engine.counters(); }
  /// A peer's latest StatsReport; nullopt before its first (or for an unknown peer).
  [[nodiscard]] std::optional<StatsReport> stats(PeerId peer) const { return m_engine.stats(peer); }
  /// Frame number of the latest frame sent (0 before the first) and its Z (m by 3).
  [[nodiscard]] std::uint32_t currentFrame() const { return m_engine.currentFrame(); }
  [[nodiscard]] const Eigen::MatrixXd& coefficients() const { return m_engine.coefficients(); }
  /// The latest frame's timestamp (the drag's arrival, else the send time; session clock), valid in frameSent().
  [[nodiscard]] Micros currentFrameStamp() const { return m_frameStamp; }
  [[nodiscard]] HostDatagramChannel& channel() { return *m_channel; }
  [[nodiscard]] LevelLibrary& levels() { return *m_levels; }
  /// The session rules this host adapts (read only: events go through the host).
  [[nodiscard]] const HostEngine& engine() const { return m_engine; }

  /// Bytes queued for `peer`'s connection now (0 for an unknown peer), for tests and the UI.
  [[nodiscard]] qint64 queuedBytes(PeerId peer) const;

  // --- the host's own user (peer 1), e.g. the desktop app dragging on the host
  /// Asks for the lock (false when already asked for or held).
  bool requestLock();
  /// Releases (or cancels the request for) the lock.
  bool releaseLock();
  [[nodiscard]] const LockClient& localLock() const { return m_engine.localLock(); }
  /// Moderation (HostEngine::kick / forceReleaseLock): removes a member with Leave{Kicked}; takes the lock back
  /// from `holder` (kNoPeer: from every holder). False when `peer` is no member / it holds no lock.
  bool kick(PeerId peer, const QString& text = {});
  bool forceReleaseLock(PeerId holder = kNoPeer);
  /// Sets the constraints as the lock holder; false without the lock or with invalid ids.
  bool setConstraints(const spectral::ConstraintSet& constraints);
  /// Drags as the lock holder (one pose per handle group); false without the lock.
  bool drag(std::span<const spectral::HandleTransform> poses);
  /// The drag ended: what it changed becomes a step of the session's edit history; false without the lock.
  bool endStroke();
  /// Undoes anybody's latest step or redoes the step this user undid last (HostEngine::edit()); true when the
  /// shape changed.
  bool edit(EditAction action);
  /// The session's edit history (every committed stroke, by anyone).
  [[nodiscard]] const EditHistory& history() const { return m_engine.history(); }
  /// A saved session's shape and history (HostEngine::restoreEdits); call before anyone joined.
  bool restoreEdits(const Eigen::MatrixXd& Z, const std::vector<EditStep>& steps) {
    return m_engine.restoreEdits(Z, steps);
  }
  /// Sends the host's own user's presence (camera, pointer, dragging) to every member (HostEngine::setLocalPresence).
  void setPresence(const Presence& presence);

 signals:
  void peersChanged();
  void lockChanged();
  /// history() changed (a stroke committed, an undo or a redo, by anyone).
  void editHistoryChanged();
  void frameSent(std::uint32_t frame);
  void statsReported(sc::session::PeerId peer, const sc::session::StatsReport& report);
  void logMessage(const QString& message);
  /// A member's presence arrived (author = its peer id); relayed to the other members already.
  void presenceReceived(const sc::session::Presence& presence);

 private:
  void acceptConnections();
  void watch(HostPeerConnection* connection);
  bool resolveIdentity(QString* error);
  void onClosed(HostPeerConnection* connection);
  void onLevelReady(std::uint32_t target);
  void onLevelFailed(std::uint32_t target, const QString& reason);
  void onTimer();

  /// Carries out the engine's actions in order, then arms the timer at its wake-up.
  void apply(HostActions actions);
  void applyOne(const HostAction& action);
  /// Reports every connection's outgoing queue to the engine and carries out what it answers (not re-entered).
  void reportSendQueues();
  void broadcast(const ControlMessage& message);
  void startTransfer(const StartTransfer& transfer);
  /// Runs the engine's deformer().prepare() on m_solver, then onConstraintsPrepared() on this thread.
  void prepareConstraints(const PrepareConstraints& job);
  void closePeer(const ClosePeer& close);
  [[nodiscard]] HostPeerConnection* connection(PeerId id) const;

  std::shared_ptr<const HostModel> m_model;
  SessionHostOptions m_options;
  std::optional<SessionSecret> m_secret;
  std::shared_ptr<const TlsIdentity> m_identity;
  TlsServer* m_server = nullptr;
  HostDatagramChannel* m_channel = nullptr;
  LevelLibrary* m_levels = nullptr;
  QTimer* m_timer = nullptr;                      ///< single-shot, armed at the engine's wake-up
  QThreadPool* m_solver = nullptr;                ///< one thread: members' constraint factorisations (child)
  std::map<PeerId, HostPeerConnection*> m_peers;  ///< every open connection, welcomed or not (children)
  HostEngine m_engine;
  Micros m_frameStamp{0};
  bool m_started = false;
  bool m_reportingQueues = false;
};

/// The admission limits' key of an address: IPv4 (and IPv4-mapped IPv6) addresses as themselves, other IPv6
/// addresses by their /64 prefix ("2001:db8:1:2::/64"), since one host usually holds a whole /64.
std::string admissionAddressKey(const QHostAddress& address);

}  // namespace sc::session
