#pragma once
// The client's session rules without sockets (docs/protocol.md, "Sequence" and "Rules"; ENet's protocol.c apart
// from unix.c): it takes the adapter's events with the clock injected (Micros now, session_clock.h) and returns
// the ClientActions to execute (client_actions.h), and tells when it next wants tick() (nextWakeUp()), so that the
// adapter (SessionClient over TLS and UDP) keeps one timer and only translates.
//
// States (ClientState; one changeState() emits StateChanged):
//   Idle --start()--> Connecting --onSecured()--> Handshaking --Welcome, onDatagramsOpened()--> Loading
//   Loading --onLevelDecoded(level)--> Ready
//   any --Leave from the host / leave()--> Left (errorText(): leaveText() of the host's Leave; leaveReason());
//   any --refusal, error, silence--> Failed (reason in errorText(): the host's Refused text, the transport's error, …;
//   once joined, a host that vanished without a Leave reads "host lost: <why>"). Left and Failed are final; the last
//   level stays readable.
// Rules
//   - Welcome: OpenDatagrams; once opened, Loading and a ResolutionRequest{level} (levelFraction, when set,
//     overrides level with round(fraction · n); ≥ 1 or not > 0 means full, 0).
//   - Progressive join (ClientEngineConfig::progressive, issue 17 item 4): the first request is
//     ResolutionRequest{kSmallestLevel} instead (the host serves its smallest rung, or its full model when it has no
//     ladder) and the wanted level is deferred. When that preview transfer completes (or fails), the wanted level is
//     requested, so it streams while the preview decodes and shows, unless the preview already is it (the full model
//     for a full request; the LevelList's closest level when the list is complete; a ladder of one level). A
//     requestResolution() while the preview is still on its way replaces the deferred choice (the newest choice
//     wins; nothing is sent until the preview completes). The preview's decoded result is installed even when the
//     wanted level's transfer completed meanwhile (then that one decodes next). Frames keep applying to the shown
//     level; installing the wanted one publishes the latest Z on it (no return to rest). levelPending() tells
//     whether the requested level is still to come (the GUI's progress bar, the CLI's and lab's "level ready").
//   - While Loading or Ready, every second from the join: the host-silence check (nothing heard for hostTimeout
//     fails the session, "host lost: not responding for <t> s"), else a Heartbeat (sequence 0, 1, …) and a
//     StatsReport (the sampler's figures, the displayed level's vertex count, setDistortion()'s figures; figures
//     that are not finite and > 0 are sent as 0).
//   - Lock: a LockClient from the Welcome; a Renew is sent at its nextRenewDue() while held; requestLock(),
//     releaseLock(), sendConstraints(), sendDrag() return no action (refused) unless live and, for drags, held.
//   - Levels: a completed transfer is decoded by the adapter, one at a time; a transfer completed while another
//     decodes waits and supersedes it (the running one's result is dropped, only the latest is installed); a
//     result arriving after leave or failure is dropped; a bad one emits LevelFailed and keeps the previous level.
//   - A hostile host (docs/security.md, "Hostile host") fails the session with a readable reason: a Welcome whose
//     model no transfer could carry, a LevelList whose sizes its counts do not imply (checkLevelList), a ModelBegin
//     of a size no listed level has (checkAnnouncement), all before a byte of the transfer is kept. One transfer
//     in flight: a ModelBegin frees the unfinished transfer and a completed one waiting to decode.
//   - Keyframes of this session's m are seeded (SeedKeyframe), others ignored; absurd ones (not displayable()) are
//     dropped and counted (framesRefused()), as are datagram frames the adapter asks admitFrame() about.
//   - Frames: onFrameChanged() only marks the frame dirty and wakes at once; the next tick() publishes it once
//     (PublishFrame), however many changes came before; installing a level publishes at once.
// Network input never asserts; decode errors and unexpected messages fail the session with a readable reason.
// Not thread-safe. Cost: O(1) per event but for Keyframes (O(m)) and the messages' own encoding.

#include "session/engine/client_actions.h"
#include "session/engine/client_level_decode.h"
#include "session/engine/handshake_client.h"
#include "session/engine/lock_client.h"
#include "session/engine/receiver_statistics.h"
#include "session/wire/control_messages.h"
#include "session/wire/model_transfer.h"
#include "spectral/display_level.h"

#include <QtCore/QString>

#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>

namespace sc::session {

/// What a client shows for the host's Leave: "The host ended the session." or "The host removed you from the
/// session.", plus the host's optional text in parentheses (plain text: show it as such).
QString leaveText(const Leave& leave);

struct ClientEngineConfig {
  QString name;                         ///< display name, ≤ kMaxNameBytes UTF-8
  std::optional<QString> password;      ///< answers a Challenge; never sent
  std::uint32_t level = 0;              ///< wanted display resolution in vertices; 0 = full
  std::optional<double> levelFraction;  ///< overrides `level` once the Welcome tells n (see the rules above)
  Millis hostTimeout{10000};            ///< a host silent this long fails the session
  /// The fewest PBKDF2 iterations a Challenge may ask for (ClientHandshakeConfig::minIterations).
  std::uint32_t minPbkdf2Iterations = kMinPbkdf2Iterations;
  /// Keep the installed level's wire payload (levelPayload()) for tests and diagnostics; by default it is freed once
  /// the level is decoded (the DisplayLevel is what the client shows).
  bool keepLevelPayload = false;
  /// Progressive join (see the rules above): the smallest level first, then the wanted one in the background.
  bool progressive = false;
};

/// The datagram receiver's figures for a StatsReport (ReceiverStatistics::report() starts a new loss interval:
/// the engine samples once per report).
struct ReceiverSample {
  ReceiverReport report;
  std::uint64_t framesApplied = 0;
  std::uint64_t dropped = 0;
};
using ReceiverSampler = std::function<ReceiverSample(Micros now)>;

class ClientEngine {
 public:
  static constexpr Micros kSecond{1'000'000};  ///< heartbeat, StatsReport and host-silence cadence
  /// The ResolutionRequest of a progressive join's preview: the host's pick() of 1 vertex is its smallest rung.
  static constexpr std::uint32_t kSmallestLevel = 1;

  explicit ClientEngine(ClientEngineConfig config);

  // --- the adapter's events
  /// Idle → Connecting, Connect. Nothing from any other state.
  ClientActions start();
  /// The connection is secured (its certificate accepted): Handshaking, the Hello. `channelBinding`: SHA-256 of
  /// the certificate the host showed (the password proof is bound to it).
  ClientActions onSecured(QByteArray channelBinding, Micros now);
  /// Any bytes arrived from the host (the silence clock).
  void onHeard(Micros now) { m_lastHeard = now; }
  /// One decoded control message or the frame reader's error. Feed them one at a time, executing the actions in
  /// between, while acceptsMessages().
  ClientActions onMessage(const ControlDecodeResult& result, Micros now);
  /// A DerivePasswordKey's result (derivePasswordKey of its request): the ChallengeResponse. Ignored unless the
  /// handshake still waits for it.
  ClientActions onPasswordKey(const QByteArray& key);
  /// The OpenDatagrams action succeeded: Loading, the ResolutionRequest, the cadence starts.
  ClientActions onDatagramsOpened(Micros now);
  /// The connection closed without our asking: Failed, with the reason the state implies.
  ClientActions onClosed();
  /// The transport failed (`text`: its error); once joined the reason reads "host lost: <text>".
  ClientActions onTransportError(const QString& text);
  /// Fails the session with `reason` (nothing once Left or Failed).
  ClientActions fail(const QString& reason);
  /// A StartDecode's result.
  ClientActions onLevelDecoded(DecodedLevel result);
  /// The datagram channel's displayed Z changed (coalesced: see the rules). Ignored before a level.
  void onFrameChanged(Micros now);
  /// Whether the adapter may show the frame `Z` (what PublishFrame would show): false, and counted in
  /// framesRefused(), when an entry is not finite or beyond kMaxAbsCoordinate (an overflowing exponent, a host
  /// that sends garbage); the previous frame then stays shown. Cost: O(m).
  bool admitFrame(const Eigen::MatrixXd& Z);
  /// Runs what is due at `now`: a pending PublishFrame, the per-second duties (sampling `sample` for the
  /// StatsReport), a lock renewal.
  ClientActions tick(Micros now, const ReceiverSampler& sample);
  /// When tick() has something to do (nullopt: nothing until another event); may be ≤ now (tick at once).
  [[nodiscard]] std::optional<Micros> nextWakeUp() const;

  // --- the user's commands (no action: refused)
  ClientActions leave();
  ClientActions requestResolution(std::uint32_t wantedVertices);
  ClientActions requestLock(Micros now);
  ClientActions releaseLock(Micros now);
  ClientActions sendConstraints(std::vector<std::vector<std::uint32_t>> groups, std::vector<std::uint32_t> anchors);
  ClientActions sendDrag(std::vector<HandleTransform> handles);
  /// The drag ended (StrokeEnd): refused unless the lock is held.
  ClientActions endStroke();
  /// Asks the host to undo this user's latest step or redo the one it undid last (EditRequest); refused unless live.
  ClientActions requestEdit(EditAction action);
  /// This user's presence (author 0: the host fills in ours); no action unless live or when it breaks a limit. The
  /// caller paces it (PresenceSchedule). client_engine_presence.cpp.
  ClientActions sendPresence(Presence presence);
  /// Distortion figures (% of the bbox diagonal) for the next StatsReports.
  void setDistortion(double maxPct, double meanPct, double lastPct);

  // --- state
  [[nodiscard]] ClientState state() const { return m_state; }
  [[nodiscard]] bool live() const { return m_state == ClientState::Loading || m_state == ClientState::Ready; }
  /// True while messages are wanted (Handshaking, Loading, Ready).
  [[nodiscard]] bool acceptsMessages() const { return m_state == ClientState::Handshaking || live(); }
  [[nodiscard]] const QString& errorText() const { return m_errorText; }
  /// Why the host sent its Leave (HostEnded, Kicked); nullopt unless the session ended by the host's Leave.
  [[nodiscard]] std::optional<LeaveReason> leaveReason() const { return m_leaveReason; }
  [[nodiscard]] const ClientHandshake& handshake() const { return m_handshake; }
  [[nodiscard]] const std::optional<Welcome>& session() const { return m_session; }
  [[nodiscard]] const PeerList& peers() const { return m_peers; }
  [[nodiscard]] const LevelList& levels() const { return m_levels; }
  [[nodiscard]] const LockClient* lock() const { return m_lock.get(); }
  /// The host's latest EditLog (the session's recent edit steps), empty before the first.
  [[nodiscard]] const EditLog& editLog() const { return m_editLog; }
  [[nodiscard]] const spectral::SharedDisplayLevel& displayLevel() const { return m_level; }
  [[nodiscard]] std::uint32_t levelVertexCount() const { return m_level ? m_level->vertexCount() : 0; }
  /// The installed level's payload when ClientEngineConfig::keepLevelPayload, else empty.
  [[nodiscard]] const QByteArray& levelPayload() const { return m_levelPayload; }
  [[nodiscard]] const QString& levelError() const { return m_levelError; }
  [[nodiscard]] bool levelDecoding() const { return m_decoding; }
  [[nodiscard]] std::uint64_t keyframesReceived() const { return m_keyframes; }
  /// Frames not shown for absurd coefficients (admitFrame(), Keyframes): counted with the dropped datagrams in
  /// the StatsReport.
  [[nodiscard]] std::uint64_t framesRefused() const { return m_framesRefused; }
  /// True while the level the user asked for is still to come after a progressive join's preview: the preview is
  /// on its way or shown and the wanted level not yet installed (a failed one ends it).
  [[nodiscard]] bool levelPending() const { return m_deferredLevel.has_value() || m_wantedInFlight; }
  /// The vertex count of the level being received (the ModelBegin's), 0 when no transfer is in flight.
  [[nodiscard]] std::uint32_t transferVertexCount() const {
    return m_receiver.active() && m_receiver.current() ? m_receiver.current()->vertexCount : 0;
  }
  /// The StatsReport the engine would send with `sample`: the displayed level's vertex count, setDistortion()'s
  /// figures; every double that is not finite and > 0 reads 0 (the wire's rule). Pure.
  [[nodiscard]] StatsReport statsReport(const ReceiverSample& sample) const;
  /// PublishFrame actions so far (one per level installed plus one per coalesced batch of frame changes).
  [[nodiscard]] std::uint64_t framesPublished() const { return m_framesPublished; }
  /// Presence messages from the host with no author or our own id (ignored).
  [[nodiscard]] std::uint64_t presenceIgnored() const { return m_presenceIgnored; }

 private:
  void changeState(ClientState next, ClientActions& out);
  void fail(const QString& reason, ClientActions& out);
  void send(const ControlMessage& message, ClientActions& out);
  void sendLock(const std::optional<LockMessage>& message, ClientActions& out);
  /// requestLock() / releaseLock(): the LockClient's command, when live; LockChanged when it sends something.
  ClientActions lockCommand(std::optional<LockMessage> (LockClient::*command)(Millis), Micros now);
  void handleHandshake(HandshakeOutput handshake, ClientActions& out);
  void dispatch(const ControlMessage& message, Micros now, ClientActions& out);
  void onHostLeave(const Leave& leave, ClientActions& out);
  /// Another member's presence from the host: PresenceReceived unless its author is 0 or ourselves (dropped,
  /// counted in presenceIgnored()). client_engine_presence.cpp.
  void onPresence(const Presence& presence, ClientActions& out);
  // levels and frames (client_engine_levels.cpp)
  void onModelBegin(const ModelBegin& begin, ClientActions& out);
  void onModelChunk(const ModelChunk& chunk, ClientActions& out);
  void startDecode(LevelJob job, bool preview, ClientActions& out);
  /// A progressive join's preview transfer ended (`arrived`: its vertex count, 0 when it failed): requests the
  /// deferred wanted level unless the preview already is it.
  void requestDeferredLevel(std::uint32_t arrived, ClientActions& out);
  void install(DecodedLevel& decoded, bool preview, ClientActions& out);
  void onKeyframe(const Keyframe& keyframe, ClientActions& out);
  void publishFrame(ClientActions& out);
  // cadence (client_engine_cadence.cpp)
  void everySecond(Micros now, const ReceiverSampler& sample, ClientActions& out);

  ClientEngineConfig m_config;
  ClientState m_state = ClientState::Idle;
  QString m_errorText;
  std::optional<LeaveReason> m_leaveReason;
  ClientHandshake m_handshake;
  std::optional<Welcome> m_session;
  PeerList m_peers;
  EditLog m_editLog;
  LevelList m_levels;
  std::unique_ptr<LockClient> m_lock;
  // levels
  ModelReceiver m_receiver;
  spectral::SharedDisplayLevel m_level;
  QByteArray m_levelPayload;
  QString m_levelError;
  bool m_decoding = false;
  std::optional<LevelJob> m_nextDecode;  ///< completed while another decodes: supersedes it
  bool m_nextIsPreview = false;          ///< m_nextDecode is the progressive preview
  bool m_decodingPreview = false;        ///< the running decode is the progressive preview (installed regardless)
  std::optional<std::uint32_t> m_deferredLevel;  ///< progressive: the wanted level, asked once the preview is in
  bool m_wantedInFlight = false;                 ///< progressive: the wanted level was asked, not yet installed
  std::uint64_t m_keyframes = 0;
  std::uint64_t m_framesRefused = 0;
  // frames
  bool m_frameDirty = false;
  Micros m_dirtySince{0};
  std::uint64_t m_framesPublished = 0;
  std::uint64_t m_presenceIgnored = 0;
  // cadence
  Micros m_lastHeard{0};
  Micros m_nextSecond{0};
  std::uint32_t m_heartbeatSequence = 0;
  double m_hdMax = 0.0, m_hdMean = 0.0, m_hdLast = 0.0;
};

}  // namespace sc::session
