#pragma once
// A client of a session over real sockets (docs/protocol.md, "Sequence" and "Rules"): a thin adapter over the
// socket-free ClientEngine (session/engine/client_engine.h), which holds every session rule (states and failure
// texts, the Welcome's ResolutionRequest, heartbeat, StatsReport and host-silence cadence, lock renewal, the level
// pipeline's decisions, keyframes, the coalescing of frame updates). This class keeps only what needs the
// operating system: the TLS control connection (a TlsStream: its socket is read and decrypted on a thread of its
// own, so a busy client thread does not stall the host's sends; tls_stream.h) and its certificate check, the
// ClientDatagramChannel, ONE timer armed at the engine's nextWakeUp(), the level decode worker thread, and the
// translation of the engine's actions into socket calls and signals.
//
// States:  Idle --start()--> Connecting --connected--> Handshaking --Welcome--> Loading --level decoded--> Ready
//          (Connecting covers the TCP connect and the TLS 1.3 handshake; the Hello is sent once the host's
//          certificate passed checkFingerprint(), tls_known_hosts.h)
//          any --Leave from the host / leave()--> Left;  any --refusal, error, silence--> Failed (reason in
//          errorText(): the host's Refused text, the socket's error, …; once joined, a host that vanished without
//          a Leave (killed, crashed, unplugged, silent for hostTimeout) reads "host lost: <why>"). A failed or left
//          client keeps its last level, Z and positions(); joining again takes a new SessionClient.
//          state() is the state last announced by stateChanged() (the engine's, in signal order).
// Contracts
//   - After the Welcome: the datagram channel is bound and opened toward the host's address and udpPort, and a
//     ResolutionRequest{options.level} is sent. A new level replaces the displayed one only once it is complete and
//     decoded; a bad payload (checksum, decode, or shape not matching the Welcome) emits levelFailed(reason) and
//     keeps the connection and the previous level.
//   - Level decoding off the client's thread: the last chunk only completes the reassembly; the SHA-256 check,
//     decodeResolutionLevel, the shape check and the interleaved rest positions (session::decodeLevel) run on one
//     worker std::thread at a time, so heartbeats and datagrams are never stuck behind them. The result comes back
//     through a queued call (levelReady()/levelFailed() are emitted on the client's thread); until then the
//     previous level stays displayed (levelDecoding() is true). A transfer completed while another decodes waits,
//     and supersedes it: only the latest completed transfer is installed. A result arriving after leave() or a
//     failure is dropped. The destructor joins a running decode (nothing is delivered to the dead object).
//   - A Keyframe seeds the channel (ignored by it once a datagram frame arrived) and is re-emitted as
//     keyframeReceived(frame, Z) (exact references for a DistortionProbe).
//   - requestLock()/releaseLock() go through the LockClient (a Renew is sent when due while held);
//     sendConstraints()/sendDrag() refuse locally (return false, send nothing) unless the lock is held, and stamp
//     the held epoch.
//   - Heartbeat every second; a StatsReport every second from the channel's report() and the distortion figures
//     set with setDistortion(); a host silent for options.hostTimeout fails the session.
// Frame path (docs/architecture.md): views take displayLevel() (signal displayLevelChanged: the level, shared and
//   immutable, K held once per process) and the frame value (signal frameUpdated: frame number and Z, float32
//   m by 3), and reconstruct X̂' + K·Z themselves (the shader, or spectral::reconstruct); they never call
//   positions(). A Z change (frameUpdated of the channel, once per applied datagram or seed) only marks the frame
//   dirty and wakes the timer at once, so every datagram already pending is decoded first and one update (one
//   frameUpdated, then one positionsUpdated(frame)) serves them all; installing a level updates at once. Z is
//   converted once per update, channel (double) → displayFrame().Z (float, in place), and passed by reference.
//   A Z with an entry that is not finite or beyond kMaxAbsCoordinate is not shown (ClientEngine::admitFrame():
//   the previous frame stays, the frame is counted as dropped in the StatsReport).
//   positions() = X̂' + K·Z (float32, interleaved xyz) is a convenience for headless users (CLI, tests): it runs
//   spectral::reconstruct on its first call after an update (O(n'·m)) and caches the result.
// Link rate: with impairment->rate.bitsPerSecond > 0, one LinkRate (link_rate.h) is the client's access link:
//   datagrams pass it in the channel's NetworkImpairment (delayed, tail-dropped when its queue is full), and the
//   TLS stream is read only as fast as the same bucket allows: each readyRead (or the link timer) reads at most
//   available() bytes, consumes them, and, when it got all it asked for (more may wait, decrypted or not),
//   re-arms a precise single-shot timer at availableAt(4 KiB). The socket's read buffer is bounded (kLinkReadBuffer),
//   and so is its kernel receive buffer (20 ms at the rate, ≥ 64 KiB, set once connected when the rate is set from the
//   start), so that TCP's flow control backs up to the host as over a real slow path; nothing on the stream is dropped.
//   The bytes charged are those read (TLS plaintext). A Leave or anything else still buffered when the host closes is
//   read at once (the close is not held back).
// Network input never asserts; decode errors and unexpected messages fail the session with a readable reason.

#include "session/engine/client_engine.h"
#include "session/engine/handshake_client.h"
#include "session/engine/lock_client.h"
#include "session/net/client_datagram_channel.h"
#include "session/wire/control_frame.h"
#include "session/wire/control_messages.h"
#include "spectral/display_level.h"
#include "spectral/resolution_level.h"

#include <Eigen/Core>
#include <QtCore/QObject>
#include <QtCore/QString>

#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <thread>
#include <utility>
#include <vector>

class QTimer;

namespace sc::session {

class TlsStream;

struct SessionClientOptions {
  QString host = QStringLiteral("127.0.0.1");  ///< host name or address of the session host
  quint16 port = 0;                            ///< the host's TCP port
  QString name;                                ///< display name, ≤ kMaxNameBytes UTF-8
  std::optional<QString> password;
  std::uint32_t level = 0;  ///< wanted display resolution in vertices; 0 = full
  /// When set (in (0, 1)), overrides `level` with round(fraction · n) once the Welcome tells n, so that a client
  /// can ask for "20 %" without knowing the mesh; 1 or more means full resolution.
  std::optional<double> levelFraction;
  /// What lost datagrams show (frame_predictor.h): Extrapolate by default (safe at pauses: the host's still frame,
  /// still_frame_schedule.h); HoldLast and ZeroFill stay selectable.
  Concealment concealment = Concealment::Extrapolate;
  /// Simulated network conditions on receive. Its rate (impairment->rate, issue 17) applies to everything this
  /// client receives: one LinkRate shared by the datagram channel and the TLS stream reader (see "Link rate").
  std::optional<ImpairmentSettings> impairment;
  std::chrono::milliseconds hostTimeout{10000};  ///< a host silent this long fails the session
  /// A Challenge asking for fewer PBKDF2 iterations is refused without a proof (password_auth.h): only tests
  /// whose hosts use fewer lower it.
  std::uint32_t minPbkdf2Iterations = kMinPbkdf2Iterations;
  QByteArray fingerprint;         ///< pinned SHA-256 of the host's certificate; empty: see trustOnFirstUse
  bool trustOnFirstUse = false;   ///< remember the first fingerprint per host:port (KnownHosts), refuse a change
  QString knownHostsFile;         ///< KnownHosts store; empty: the application's QSettings
  bool keepLevelPayload = false;  ///< keep the installed level's wire payload (levelPayload()): tests, diagnostics
  /// Progressive join (ClientEngine's rules, issue 17 item 4): the host's smallest level first, shown live, then
  /// the wanted one streamed in the background (levelPending(), transferVertexCount()). The app's joins (GUI, CLI,
  /// lab) turn it on.
  bool progressive = false;
};

class SessionClient final : public QObject {
  Q_OBJECT
  Q_DISABLE_COPY_MOVE(SessionClient)

 public:
  enum class State { Idle, Connecting, Handshaking, Loading, Ready, Left, Failed };
  Q_ENUM(State)

  explicit SessionClient(SessionClientOptions options, QObject* parent = nullptr);
  ~SessionClient() override;

  /// Connects to options.host:options.port (from Idle only).
  void start();
  /// Sends Leave (once joined) and closes (state Left). Nothing from Idle, Left or Failed. Destroying a joined
  /// client without leave() just drops the connection (the host notices at once).
  void leave();
  /// Asks the host for another display resolution (0 = full); the current level stays until the new one is in.
  bool requestResolution(std::uint32_t wantedVertices);

  bool requestLock();
  bool releaseLock();
  /// Handle groups and anchors (full-resolution vertex ids) for the following drags; false without the lock.
  bool sendConstraints(std::vector<std::vector<std::uint32_t>> groups, std::vector<std::uint32_t> anchors);
  /// One 3×4 affine per handle group; false without the lock or when the message breaks a limit.
  bool sendDrag(std::vector<HandleTransform> handles);
  /// The drag ended: the host records what it changed as this user's step (StrokeEnd); false without the lock.
  bool endStroke();
  /// Asks the host to undo this user's latest step or redo the one it undid last; false unless joined.
  bool requestEdit(EditAction action);
  /// The host's latest EditLog (the session's recent edit steps).
  [[nodiscard]] const EditLog& editLog() const { return m_engine.editLog(); }
  /// This user's presence to the host (relayed to the others); false when not live or out of bounds.
  bool sendPresence(const Presence& presence);
  /// Changes the simulated network conditions on receive, live (ClientDatagramChannel::setImpairment: datagrams
  /// the old impairment holds back are delivered at once); nullopt removes them. Also before start().
  /// A new rate starts a fresh bucket (full) shared by both paths; no rate reads the stream unthrottled again.
  void setImpairment(std::optional<ImpairmentSettings> settings);
  [[nodiscard]] const std::optional<ImpairmentSettings>& impairment() const { return m_options.impairment; }
  /// The link's bottleneck in use (nullptr without a rate): its counters show the stream's and datagrams' bytes.
  [[nodiscard]] const LinkRate* link() const { return m_link.get(); }
  /// Bytes read from the TLS stream so far (plaintext: control messages and level transfers).
  [[nodiscard]] std::uint64_t streamBytesRead() const { return m_streamBytesRead; }
  /// Distortion figures (% of the bbox diagonal) reported in the next StatsReports.
  void setDistortion(double maxPct, double meanPct, double lastPct);
  /// What the next StatsReport would say now (ClientEngine::statsReport() over the channel's peek(): no new loss
  /// interval starts), for a UI showing this client's own figures without reaching into channel().
  [[nodiscard]] StatsReport peekStats() const;

  [[nodiscard]] State state() const { return m_state; }
  [[nodiscard]] const QString& errorText() const { return m_engine.errorText(); }
  /// Why the host ended this client's session (its Leave's reason); nullopt unless the host sent a Leave.
  [[nodiscard]] std::optional<LeaveReason> leaveReason() const { return m_engine.leaveReason(); }
  /// SHA-256 of the certificate the host showed (empty before the TLS handshake ends; set also when the
  /// fingerprint check refused it, so that the UI can show both).
  [[nodiscard]] const QByteArray& hostFingerprint() const { return m_hostFingerprint; }
  /// The handshake (its refusal() holds the host's reason when it refused us).
  [[nodiscard]] const ClientHandshake& handshake() const { return m_engine.handshake(); }
  /// The Welcome (peer id, m, n, udpPort); nullopt before it.
  [[nodiscard]] const std::optional<Welcome>& session() const { return m_engine.session(); }
  [[nodiscard]] PeerId peerId() const { return session() ? session()->peerId : kNoPeer; }
  [[nodiscard]] const PeerList& peers() const { return m_engine.peers(); }
  /// The host's built levels with exact vertex/face counts (LevelList; empty until the first one arrives).
  /// requestResolution(closestLevel(levels(), n)->vertexCount) gets exactly that level.
  [[nodiscard]] const LevelList& levels() const { return m_engine.levels(); }
  /// The lock state machine (nullptr before the Welcome).
  [[nodiscard]] const LockClient* lock() const { return m_engine.lock(); }
  /// The displayed level (nullptr before the first is complete), its payload bytes as received, its vertex count.
  [[nodiscard]] const spectral::ResolutionLevel* level() const {
    return displayLevel() ? &displayLevel()->level : nullptr;
  }
  /// The displayed level, shared and immutable (nullptr before the first is complete): a view holds this pointer,
  /// never a copy of K (one float K per process, docs/architecture.md).
  [[nodiscard]] const spectral::SharedDisplayLevel& displayLevel() const { return m_engine.displayLevel(); }
  /// The displayed frame: positionsFrame() and positionsCoefficients() as one value (what frameUpdated carried).
  [[nodiscard]] const spectral::DisplayFrame& displayFrame() const { return m_frame; }
  [[nodiscard]] const QByteArray& levelPayload() const { return m_engine.levelPayload(); }
  [[nodiscard]] std::uint32_t levelVertexCount() const { return m_engine.levelVertexCount(); }
  [[nodiscard]] const QString& levelError() const { return m_engine.levelError(); }
  /// True while a completed transfer is being checked and decoded off-thread (the previous level is still shown).
  [[nodiscard]] bool levelDecoding() const { return m_engine.levelDecoding(); }
  /// A progressive join's wanted level is still to come (the preview is on its way or shown).
  [[nodiscard]] bool levelPending() const { return m_engine.levelPending(); }
  /// The vertex count of the level being received, 0 when no transfer is in flight.
  [[nodiscard]] std::uint32_t transferVertexCount() const { return m_engine.transferVertexCount(); }
  /// X̂' + K·Z for Z = positionsCoefficients(), 3·n' floats (empty before a level). Reconstructed here on the first
  /// call after an update (O(n'·m), spectral::reconstruct), then cached. For headless users: views take
  /// displayLevel() and frameUpdated instead.
  [[nodiscard]] const std::vector<float>& positions() const;
  /// The m by 3 Z (float32) that positions() reflects: the channel's coefficients at the last update (zero before
  /// the first frame); empty before a level.
  [[nodiscard]] const Eigen::MatrixXf& positionsCoefficients() const { return m_frame.Z; }
  /// Wall time of the last reconstruction positions() ran, milliseconds (0 before the first).
  [[nodiscard]] double reconstructionMs() const { return m_reconstructionMs; }
  /// Frame number of the Z that positions() reflects (the channel's current frame at the last update).
  [[nodiscard]] std::uint32_t positionsFrame() const { return m_frame.frame; }
  /// How many times positions() was updated (one per level installed, plus at most one per event-loop pass in
  /// which Z changed, however many datagrams changed it); each update emits positionsUpdated() once.
  [[nodiscard]] std::uint64_t positionUpdates() const { return m_engine.framesPublished(); }
  [[nodiscard]] std::uint64_t keyframesReceived() const { return m_engine.keyframesReceived(); }
  [[nodiscard]] ClientDatagramChannel& channel() { return *m_channel; }
  [[nodiscard]] const ClientDatagramChannel& channel() const { return *m_channel; }

 signals:
  void stateChanged(sc::session::SessionClient::State state);
  void failed(const QString& reason);
  void levelReady(std::uint32_t vertexCount);
  void levelFailed(const QString& reason);
  void modelProgress(quint64 received, quint64 total);
  void lockChanged();
  void peersChanged();
  /// editLog() changed.
  void editLogChanged();
  /// A LevelList arrived (levels() changed).
  void levelsChanged();
  void keyframeReceived(std::uint32_t frame, const Eigen::MatrixXd& Z);
  void positionsUpdated(std::uint32_t frame);
  /// A new level is displayed (emitted before levelReady()); the frame path's level, pushed down to views.
  void displayLevelChanged(const sc::spectral::SharedDisplayLevel& level);
  /// The displayed frame changed (emitted just before positionsUpdated(), with the same frame): the frame path's
  /// value, pushed down to views, so that nobody pulls Z back through the client.
  void frameUpdated(const sc::spectral::DisplayFrame& frame);
  /// Another member's presence (author = its peer id) arrived.
  void presenceReceived(const sc::session::Presence& presence);

 private:
  /// Executes the engine's actions in order (session_client_actions.cpp; StartDecode and PublishFrame in
  /// session_client_level.cpp), then re-arms the timer.
  void apply(ClientActions actions);
  /// apply() for a user command: false when the engine refused it (no action).
  bool applyCommand(ClientActions actions);
  void execute(client_action::Connect);
  void execute(client_action::Send& send);
  void execute(client_action::StateChanged changed);
  void execute(client_action::OpenDatagrams& open);
  void execute(client_action::CloseDatagrams);
  void execute(client_action::Disconnect disconnect);
  void execute(client_action::Failed& failure);
  void execute(client_action::Notify notify);
  void execute(client_action::ModelProgress progress);
  void execute(client_action::SeedKeyframe& keyframe);
  void execute(client_action::StartDecode& decode);
  void execute(client_action::LevelFailed& failure);
  void execute(client_action::LevelReady ready);
  void execute(client_action::PublishFrame);
  void execute(client_action::PresenceReceived& received) { emit presenceReceived(received.presence); }
  void execute(client_action::DerivePasswordKey& derive);
  void armTimer();
  void wake();
  [[nodiscard]] ReceiverSample sampleReceiver(Micros now);
  void readAvailable();
  /// Reads what the link allows (everything without a rate, or with `unthrottled`) and hands it to the engine.
  void readStream(bool unthrottled);
  /// Makes m_link from m_options.impairment (or none) and bounds the socket's read buffer accordingly.
  void makeLink();
  /// Lets the TLS stream read ahead kControlReadAhead + `transferBytes` (capped) when no link rate is set.
  void grantReadAhead(std::uint64_t transferBytes);
  void onEncrypted();
  /// The decode worker's result, on this object's thread.
  void finishDecode(DecodedLevel& result);
  void finishPasswordKey(QByteArray& key);

  SessionClientOptions m_options;
  ClientEngine m_engine;
  State m_state = State::Idle;    ///< as last announced by stateChanged()
  TlsStream* m_stream = nullptr;  ///< the control connection, read on a thread of its own
  qint64 m_readAhead = 0;         ///< the stream's read limit granted by grantReadAhead() (0: none yet)
  QByteArray m_hostFingerprint;
  ClientDatagramChannel* m_channel = nullptr;
  QTimer* m_timer = nullptr;         ///< single-shot, armed at m_engine.nextWakeUp()
  std::shared_ptr<LinkRate> m_link;  ///< the access link's bucket (null: no rate)
  QTimer* m_linkTimer = nullptr;     ///< single-shot, precise: the stream's next read under the link rate
  std::uint64_t m_streamBytesRead = 0;
  std::optional<Micros> m_armedFor;
  ControlFrameReader m_reader;
  std::thread m_keyDeriver;  ///< the password key (PBKDF2, up to a second) for the Challenge; the destructor joins it
  std::thread m_decoder;     ///< one level decode at a time (the engine decides); the destructor joins it
  spectral::DisplayFrame m_frame;          ///< the displayed frame (Z float m by 3; empty before a level)
  mutable std::vector<float> m_positions;  ///< a cache: X̂' + K·m_frame.Z once m_positionsStale is false
  mutable bool m_positionsStale = false;
  mutable double m_reconstructionMs = 0.0;
};

}  // namespace sc::session
