#pragma once
// A client of a session over real sockets (docs/protocol.md, "Sequence" and "Rules"): the TCP control connection
// (ClientHandshake, then session messages), a ClientDatagramChannel for the coefficient frames, a ModelReceiver
// for the level transfer, a LockClient, and the reconstruction X' = X̂' + K·Z of the received level. A thin
// adapter: protocol decisions are the pure state machines'; this class wires them to sockets and timers.
//
// States:  Idle --start()--> Connecting --connected--> Handshaking --Welcome--> Loading --level decoded--> Ready
//          (Connecting covers the TCP connect and the TLS 1.3 handshake; the Hello is sent once the host's
//          certificate passed checkFingerprint(), tls_known_hosts.h)
//          any --Leave from the host / leave()--> Left;  any --refusal, error, silence--> Failed (reason in
//          errorText(): the host's Refused text, the socket's error, …; once joined, a host that vanished without
//          a Leave (killed, crashed, unplugged, silent for hostTimeout) reads "host lost: <why>"). A failed or left
//          client keeps its last level, Z and positions(); joining again takes a new SessionClient.
// Contracts
//   - After the Welcome: the datagram channel is bound and opened toward the host's address and udpPort, and a
//     ResolutionRequest{options.level} is sent. A new level replaces the displayed one only once it is complete and
//     decoded; a bad payload (checksum, decode, or shape not matching the Welcome) emits levelFailed(reason) and
//     keeps the connection and the previous level.
//   - Level decoding off the client's thread: the last chunk only completes the reassembly; the SHA-256 check,
//     decodeResolutionLevel, the shape check and the interleaved rest positions run on one worker std::thread at
//     a time, so heartbeats and datagrams are never stuck behind them. The result comes back through a queued call
//     (levelReady()/levelFailed() are emitted on the client's thread); until then the previous level stays
//     displayed (levelDecoding() is true). A transfer completed while another decodes waits, and supersedes it:
//     only the latest completed transfer is installed. A result arriving after leave() or a failure is dropped.
//     The destructor joins a running decode (it waits for it to finish; nothing is delivered to the dead object).
//   - A Keyframe seeds the channel (ignored by it once a datagram frame arrived) and is re-emitted as
//     keyframeReceived(frame, Z) (exact references for a DistortionProbe).
//   - requestLock()/releaseLock() go through the LockClient (renewed every 250 ms poll while held);
//     sendConstraints()/sendDrag() refuse locally (return false, send nothing) unless the lock is held, and stamp
//     the held epoch.
//   - Heartbeat every second; a StatsReport every second from the channel's report() and the distortion figures
//     set with setDistortion(); a host silent for options.hostTimeout fails the session.
//   - positions() = X̂' + K·Z (float32, interleaved xyz) for positionsCoefficients(), the Z of positionsFrame(),
//     updated at once when a level is installed and, when Z changes (frameUpdated of the channel, once per applied
//     datagram or seed), coalesced: Z changes only mark the positions dirty and arm a zero-timeout single-shot
//     timer, so every datagram already pending is decoded first and one update (one positionsUpdated(frame)) serves
//     them all. The O(n'·m) reconstruction itself runs on the first positions() call after an update, so a view that
//     reconstructs from K and positionsCoefficients() itself (MeshViewport) does not pay for it twice.
// Network input never asserts; decode errors and unexpected messages fail the session with a readable reason.

#include "session/engine/handshake_client.h"
#include "session/engine/lock_client.h"
#include "session/net/client_datagram_channel.h"
#include "session/wire/control_frame.h"
#include "session/wire/control_messages.h"
#include "session/wire/model_transfer.h"
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

class QSslSocket;
class QTimer;

namespace sc::session {

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
  std::optional<ImpairmentSettings> impairment;  ///< simulated network conditions on receive
  std::chrono::milliseconds hostTimeout{10000};  ///< a host silent this long fails the session
  QByteArray fingerprint;        ///< pinned SHA-256 of the host's certificate; empty: see trustOnFirstUse
  bool trustOnFirstUse = false;  ///< remember the first fingerprint per host:port (KnownHosts), refuse a change
  QString knownHostsFile;        ///< KnownHosts store; empty: the application's QSettings
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
  /// Changes the simulated network conditions on receive, live (ClientDatagramChannel::setImpairment: datagrams
  /// the old impairment holds back are delivered at once); nullopt removes them. Also before start().
  void setImpairment(std::optional<ImpairmentSettings> settings);
  [[nodiscard]] const std::optional<ImpairmentSettings>& impairment() const { return m_options.impairment; }
  /// Distortion figures (% of the bbox diagonal) reported in the next StatsReports.
  void setDistortion(double maxPct, double meanPct, double lastPct);

  [[nodiscard]] State state() const { return m_state; }
  [[nodiscard]] const QString& errorText() const { return m_errorText; }
  /// SHA-256 of the certificate the host showed (empty before the TLS handshake ends; set also when the
  /// fingerprint check refused it, so that the UI can show both).
  [[nodiscard]] const QByteArray& hostFingerprint() const { return m_hostFingerprint; }
  /// The handshake (its refusal() holds the host's reason when it refused us).
  [[nodiscard]] const ClientHandshake& handshake() const { return m_handshake; }
  /// The Welcome (peer id, m, n, udpPort); nullopt before it.
  [[nodiscard]] const std::optional<Welcome>& session() const { return m_session; }
  [[nodiscard]] PeerId peerId() const { return m_session ? m_session->peerId : kNoPeer; }
  [[nodiscard]] const PeerList& peers() const { return m_peers; }
  /// The host's built levels with exact vertex/face counts (LevelList; empty until the first one arrives).
  /// requestResolution(closestLevel(levels(), n)->vertexCount) gets exactly that level.
  [[nodiscard]] const LevelList& levels() const { return m_levels; }
  /// The lock state machine (nullptr before the Welcome).
  [[nodiscard]] const LockClient* lock() const { return m_lock.get(); }
  /// The displayed level (nullptr before the first is complete), its payload bytes as received, its vertex count.
  [[nodiscard]] const spectral::ResolutionLevel* level() const { return m_level ? &m_level->level : nullptr; }
  /// The displayed level, shared and immutable (nullptr before the first is complete): a view holds this pointer,
  /// never a copy of K (one float K per process, docs/architecture.md).
  [[nodiscard]] const spectral::SharedDisplayLevel& displayLevel() const { return m_level; }
  /// The frame that positions() reflects: positionsFrame() and positionsCoefficients() as one value.
  [[nodiscard]] spectral::DisplayFrame displayFrame() const { return {m_positionsFrame, m_positionsZ}; }
  [[nodiscard]] const QByteArray& levelPayload() const { return m_levelPayload; }
  [[nodiscard]] std::uint32_t levelVertexCount() const;
  [[nodiscard]] const QString& levelError() const { return m_levelError; }
  /// True while a completed transfer is being checked and decoded off-thread (the previous level is still shown).
  [[nodiscard]] bool levelDecoding() const { return m_decoding; }
  /// X̂' + K·Z for Z = positionsCoefficients(), 3·n' floats (empty before a level). Reconstructed here on the first
  /// call after an update (O(n'·m), spectral::reconstructInterleaved), then cached.
  [[nodiscard]] const std::vector<float>& positions() const;
  /// The m by 3 Z (float32) that positions() reflects: the channel's coefficients at the last update (zero before
  /// the first frame); empty before a level.
  [[nodiscard]] const Eigen::MatrixXf& positionsCoefficients() const { return m_positionsZ; }
  /// Wall time of the last reconstruction positions() ran, milliseconds (0 before the first).
  [[nodiscard]] double reconstructionMs() const { return m_reconstructionMs; }
  /// Frame number of the Z that positions() reflects (the channel's current frame at the last update).
  [[nodiscard]] std::uint32_t positionsFrame() const { return m_positionsFrame; }
  /// How many times positions() was updated (one per level installed, plus at most one per event-loop pass in
  /// which Z changed, however many datagrams changed it); each update emits positionsUpdated() once.
  [[nodiscard]] std::uint64_t positionUpdates() const { return m_positionUpdates; }
  [[nodiscard]] std::uint64_t keyframesReceived() const { return m_keyframes; }
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
  /// A LevelList arrived (levels() changed).
  void levelsChanged();
  void keyframeReceived(std::uint32_t frame, const Eigen::MatrixXd& Z);
  void positionsUpdated(std::uint32_t frame);
  /// A new level is displayed (emitted before levelReady()); the frame path's level, pushed down to views.
  void displayLevelChanged(const sc::spectral::SharedDisplayLevel& level);
  /// The displayed frame changed (emitted just before positionsUpdated(), with the same frame): the frame path's
  /// value, pushed down to views, so that nobody pulls Z back through the client.
  void frameUpdated(const sc::spectral::DisplayFrame& frame);

 private:
  void changeState(State next);
  void fail(const QString& reason);
  void send(const ControlMessage& message);
  void sendLock(const std::optional<LockMessage>& message);
  void readAvailable();
  void onEncrypted();
  void handleHandshake(const HandshakeOutput& out);
  void onJoined();
  void onMessage(const ControlMessage& message);
  struct DecodedLevel;
  /// Runs on the worker thread: checksum, decode, shape check (m, n of the Welcome), interleaved rest positions.
  static DecodedLevel decodeLevel(QByteArray payload, const QByteArray& expectedSha256, std::uint16_t rowCount,
                                  std::uint32_t vertexCount);

  void onModelChunk(const ModelChunk& chunk);
  void startDecode(QByteArray payload, QByteArray expectedSha256);
  void finishDecode(const std::shared_ptr<DecodedLevel>& result);
  void installLevel(DecodedLevel& decoded);
  void onKeyframe(const Keyframe& keyframe);
  void onFrameUpdated();
  void updatePositions();
  void everySecond();
  void renewTick();
  [[nodiscard]] bool live() const { return m_state == State::Loading || m_state == State::Ready; }

  SessionClientOptions m_options;
  QSslSocket* m_socket = nullptr;
  QByteArray m_hostFingerprint;
  ClientDatagramChannel* m_channel = nullptr;
  QTimer* m_secondTimer = nullptr;
  QTimer* m_renewTimer = nullptr;
  QTimer* m_recomputeTimer = nullptr;  ///< zero-timeout single-shot: coalesced recompute after pending datagrams
  ControlFrameReader m_reader;
  ClientHandshake m_handshake;
  ModelReceiver m_receiver;
  State m_state = State::Idle;
  QString m_errorText;
  std::optional<Welcome> m_session;
  PeerList m_peers;
  LevelList m_levels;
  std::unique_ptr<LockClient> m_lock;
  spectral::SharedDisplayLevel m_level;  ///< the displayed level (X̂' interleaved and K inside), shared with views
  QByteArray m_levelPayload;
  QString m_levelError;
  mutable std::vector<float> m_positions;  ///< a cache: X̂' + K·m_positionsZ once m_positionsStale is false
  mutable bool m_positionsStale = false;
  mutable double m_reconstructionMs = 0.0;
  Eigen::MatrixXf m_positionsZ;
  std::uint32_t m_positionsFrame = 0;
  bool m_positionsDirty = false;
  std::uint64_t m_positionUpdates = 0;
  // level decoding (one worker at a time; the destructor joins it)
  std::thread m_decoder;
  bool m_decoding = false;
  std::optional<std::pair<QByteArray, QByteArray>> m_nextDecode;  ///< (payload, sha256) completed meanwhile
  std::uint64_t m_keyframes = 0;
  std::uint32_t m_heartbeatSequence = 0;
  std::chrono::microseconds m_lastHeard{0};
  double m_hdMax = 0.0, m_hdMean = 0.0, m_hdLast = 0.0;
};

}  // namespace sc::session
