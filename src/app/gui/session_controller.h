#pragma once
// SessionController: what a session window sees of a session (src/session), whichever role this instance plays.
// Two implementations: HostController (host_controller.h: owns a SessionHost, its own user is peer 1) and
// ClientController (client_controller.h: owns a SessionClient). Neither hands out its session object: the window
// gets what it needs through this interface (lock, constraints and drags, display data, levels, peers and
// statistics, identity, errors as readable text). No protocol or math decisions live here: they are the session's
// and the spectral module's (style.md item 1, "app is composition").
//
// The frame path, one way (docs/architecture.md): a controller pushes its display data down, never to be pulled
// back: displayLevelChanged(level) when another level is shown (shared and immutable: rest positions, faces,
// float K, built once) and frameChanged(frame) for every frame (frame number and Z, float, m by 3). A view
// reconstructs X̂' + K·Z itself (MeshViewport::setDisplayLevel/showFrame); positions() is for headless callers.
//
// Lifecycle (state()):
//   Idle --HostController::host()--> Preparing (mesh load + basis on a worker thread; progress(), cancel()) --> Live
//   Idle --ClientController::join()--> Connecting (TCP, handshake, model download; progress()) --> Live
//   Live --leave()--> Left;  any --error--> Failed (failed(text) emitted once, with readable text).
//   A controller is used for one session: after Left or Failed, make a new one to host or join again.
//
// Threading: GUI thread only (the host's preparation worker reports back through queued calls).
// Errors never throw: every failure becomes failed(QString).

#include "app/gui/constraint_editor.h"
#include "app/gui/session_settings.h"
#include "session/engine/relay_audience.h"
#include "session/wire/control_messages.h"
#include "session/wire/lock_messages.h"
#include "spectral/display_level.h"
#include "spectral/vertex_ids.h"

#include <Eigen/Core>
#include <QObject>
#include <QString>

#include <cstdint>
#include <optional>
#include <utility>
#include <vector>

class QTimer;

namespace sc::session {
class LockClient;
}

namespace sc::model {
struct SessionFile;
}

namespace sc::app {

class SessionController : public QObject, protected EditTarget {
  Q_OBJECT
  Q_DISABLE_COPY_MOVE(SessionController)

 public:
  enum class Role { None, Host, Client };  ///< None: no session (what views show without a controller)
  Q_ENUM(Role)
  enum class State { Idle, Preparing, Connecting, Live, Left, Failed };
  Q_ENUM(State)

  ~SessionController() override;

  // --- lifecycle
  [[nodiscard]] virtual Role role() const = 0;
  [[nodiscard]] State state() const { return m_state; }
  [[nodiscard]] const QString& errorText() const { return m_errorText; }
  /// Cancels a running preparation (host) or connection (client): state Failed with failed("Cancelled.").
  virtual void cancel() = 0;
  /// Whether the session failed (or is about to) because the user cancelled it: no error to report.
  [[nodiscard]] bool cancelledByUser() const { return m_cancelledByUser; }
  /// Leaves the session (client: Leave to the host; host: Leave to every peer). State Left. No-op when not
  /// Preparing, Connecting or Live.
  void leave();
  /// The host's TCP port (0 unless hosting and live).
  [[nodiscard]] virtual quint16 tcpPort() const { return 0; }
  /// This user's peer id: 1 on a host, the Welcome's id on a client, kNoPeer before.
  [[nodiscard]] virtual session::PeerId selfId() const = 0;

  // --- lock
  /// Asks for the edit lock (false when already asked for, held, or not live).
  virtual bool requestLock() = 0;
  /// Releases (or cancels the request for) the lock; ends a drag in progress.
  bool releaseLock();
  /// True when this user holds the lock (drags would be accepted).
  [[nodiscard]] bool canDrag() const final;
  /// True while the lock is requested, queued or held by this user.
  [[nodiscard]] bool lockWanted() const;
  /// Who holds the lock and where this user stands (lock_text.h); empty when not live.
  [[nodiscard]] QString lockText() const;
  /// Who holds a lock (several may drag at once, each their own handle), oldest grant first; empty when not live.
  [[nodiscard]] virtual std::vector<session::PeerId> lockHolders() const = 0;
  /// Whether `peer` is among lockHolders().
  [[nodiscard]] bool holdsLock(session::PeerId peer) const;
  /// Peers waiting for the lock, first in line first (known on a host only; empty on a client).
  [[nodiscard]] virtual std::vector<session::PeerId> lockQueue() const { return {}; }
  /// The lock button's text (lock_text.h: "Request lock", "Cancel request", "Release lock").
  [[nodiscard]] QString lockActionText() const;

  // --- moderation (host only; false on a client or when not live)
  /// Removes the member `peer` from the session (Leave{Kicked}); its lock is freed. False unless it is a member.
  virtual bool kick(session::PeerId /*peer*/) { return false; }
  /// Takes the lock back from `holder` (kNoPeer: from everybody; Released{RevokedByHost}). False when it holds none.
  virtual bool forceReleaseLock(session::PeerId /*holder*/ = session::kNoPeer) { return false; }

  // --- constraints and drags (ConstraintEditor: displayed ids, mapped to full-resolution ids when sent)
  /// The handle group; sent with the anchors at once when this user holds the lock, otherwise when it is granted.
  /// True when the constraints were sent now.
  bool setHandle(spectral::DisplayVertexIds ids) { return m_editor.setHandle(std::move(ids)); }
  bool setAnchors(spectral::DisplayVertexIds ids) { return m_editor.setAnchors(std::move(ids)); }
  /// Handle and anchors at once (one constraints message instead of two).
  bool setSelection(spectral::DisplayVertexIds handle, spectral::DisplayVertexIds anchors) {
    return m_editor.setSelection(std::move(handle), std::move(anchors));
  }
  [[nodiscard]] const spectral::DisplayVertexIds& handle() const { return m_editor.handle(); }
  [[nodiscard]] const spectral::DisplayVertexIds& anchors() const { return m_editor.anchors(); }
  /// Starts a drag of the handle: false without the lock or without a handle.
  bool beginDrag() { return m_editor.beginDrag(); }
  /// The handle's pose since beginDrag(), as MeshViewport::dragMoved gives it (ConstraintEditor::dragTo()).
  bool dragTo(const Eigen::Vector3d& translation, const Eigen::Matrix3d& rotation) {
    return m_editor.dragTo(translation, rotation);
  }
  void endDrag() { m_editor.endDrag(); }
  [[nodiscard]] bool dragging() const { return m_editor.dragging(); }
  /// The constraints this user last sent (nullopt before any reached the session).
  [[nodiscard]] std::optional<HostConstraints> sentConstraints() const { return m_editor.sent(); }
  /// Host started from a session file: that file's content (restored once live: savedSessionRestored()), else null.
  [[nodiscard]] virtual const model::SessionFile* savedSession() const { return nullptr; }

  // --- the session's shared edit history (session/engine/edit_history.h)
  /// The latest steps as the host lists them (a host's own, a client's latest EditLog); empty when not live.
  [[nodiscard]] virtual session::EditLog editLog() const = 0;
  /// Undo: a client its own latest step, the host anybody's; redo: the step this user undid last. False when not
  /// live or during a drag (a client's request may still find nothing to do: editLogChanged() tells).
  virtual bool requestEdit(session::EditAction action) = 0;
  /// The step an undo would take out now (nullopt: none): session::undoableIn(editLog()) for this user.
  [[nodiscard]] std::optional<session::EditLogEntry> undoableStep() const;
  /// The step a redo would put back now (nullopt: none): session::redoableIn(editLog()) for this user.
  [[nodiscard]] std::optional<session::EditLogEntry> redoableStep() const;

  // --- what is displayed (the values last pushed down)
  /// The displayed level (a host's is its full level), nullptr before the first.
  [[nodiscard]] const spectral::SharedDisplayLevel& displayLevel() const { return m_level; }
  /// The displayed frame (empty Z before the first frame: the rest shape).
  [[nodiscard]] const spectral::DisplayFrame& displayFrame() const { return m_frame; }
  /// The displayed level's rest positions X̂' (#V' by 3) and faces (#F' by 3); empty before the first level.
  [[nodiscard]] const Eigen::MatrixXd& displayRestPositions() const;
  [[nodiscard]] const Eigen::MatrixXi& displayFaces() const;
  [[nodiscard]] const spectral::ResolutionLevel* level() const { return m_level ? &m_level->level : nullptr; }
  /// X̂' + K·Z of the displayed level and frame, 3·#V' floats interleaved xyz (empty before the first level), for
  /// headless callers (export, tests): computed on each call with spectral::reconstruct. Cost: O(#V'·m).
  [[nodiscard]] std::vector<float> positions() const;
  /// The current coefficients Z (m by 3): a host's exact double Z; a client's displayed frame. Empty before.
  [[nodiscard]] virtual Eigen::MatrixXd coefficients() const;

  // --- levels
  /// The resolution choices (a host displays only its full level; a client's list: ClientController::levels()).
  [[nodiscard]] virtual std::vector<LevelChoice> levels() const = 0;
  /// The target last asked for (0 = full).
  [[nodiscard]] std::uint32_t levelTarget() const { return m_levelTarget; }
  /// Client: asks the host for another level (the current one stays until the new one is in). False on a host.
  virtual bool setLevel(std::uint32_t target);

  // --- emulated network conditions (client)
  /// Client: emulated loss (0..1), mean burst and delay on receive and the link rate in Mbit/s (0: unlimited; it
  /// throttles the datagrams and the TLS stream alike), live; false (nothing changed) on a host.
  virtual bool setNetworkConditions(double loss, double burstLength, int delayMs, double rateMbit);
  /// The client's current conditions (zeros: none; always zeros on a host).
  [[nodiscard]] virtual NetworkConditions networkConditions() const { return {}; }

  // --- peers and statistics
  [[nodiscard]] virtual session::PeerList peers() const = 0;
  /// A peer's latest figures: on a host every client's StatsReport; on a client only its own. nullopt when unknown.
  [[nodiscard]] virtual std::optional<session::StatsReport> stats(session::PeerId peer) const = 0;
  /// Host relaying through NATS: its viewers as one aggregate (count, loss and latency distributions; issue 18
  /// item 3). nullopt when this instance does not relay.
  [[nodiscard]] virtual std::optional<session::RelayAudienceSummary> relayAudience() const { return std::nullopt; }
  // --- presence (issue 15)
  /// Sends this user's presence (the host's own user: to every client; a client: to the host, which relays it).
  /// Nothing unless live. The caller paces it (SessionPresence, session::PresenceSchedule).
  virtual void sendPresence(const session::Presence& presence) = 0;

  /// Payload bandwidth this instance sends to `peer`, kbit/s (a host's per-client traffic; 0 on a client).
  [[nodiscard]] virtual double sentKbps(session::PeerId peer) const;

  // --- host identity (docs/security.md)
  /// SHA-256 of the host's TLS certificate: on a host its own (once live); on a client the one the host showed
  /// (once the TLS handshake ended, also when it was refused). Empty otherwise.
  [[nodiscard]] virtual QByteArray hostFingerprint() const = 0;
  /// Client: how that fingerprint was trusted (None until the certificate was accepted, and on a host).
  [[nodiscard]] virtual HostTrust hostTrust() const { return HostTrust::None; }
  /// Client: true when the join failed because the host's certificate did not match the pinned or remembered one.
  [[nodiscard]] virtual bool fingerprintRefused() const { return false; }
  /// Client: the join's settings (without a password) when it failed because the host asked for a password none
  /// was given for, or refused the one given: what to ask the user again with. nullopt otherwise.
  [[nodiscard]] virtual std::optional<JoinSettings> passwordRetry() const { return std::nullopt; }
  /// A viewer through NATS (viewer_controller.h): the status text of a read-only session ("Watching S through
  /// NATS"); nullopt for a host or a client, which may edit.
  [[nodiscard]] virtual std::optional<QString> readOnlyText() const { return std::nullopt; }

 signals:
  void stateChanged(sc::app::SessionController::State state);
  /// Another level is displayed (the frame path's level; a frameChanged() follows).
  void displayLevelChanged(const sc::spectral::SharedDisplayLevel& level);
  /// A new frame of the displayed level (the frame path's value).
  void frameChanged(const sc::spectral::DisplayFrame& frame);
  /// A new level is live (after displayLevelChanged()): re-read level-dependent figures (sizes, levels()).
  void meshChanged();
  void lockChanged();
  /// The host refused this user's handle and anchors: `message` says why, in words (whose they overlap).
  void constraintsRefused(const QString& message);
  void peersChanged();
  void statsChanged();
  /// A readable error; state() is Failed (or, for a rejected level, stays Live).
  void failed(const QString& message);
  void hostingStarted(quint16 port);
  /// setNetworkConditions() changed the client's emulated conditions.
  void networkConditionsChanged();
  /// Long work: percent 0..100 and what is being done.
  void progress(int percent, const QString& what);
  /// Client, live: a level streams in behind the shown one (a progressive join's requested level, or a resolution
  /// switch): percent 0..100 and its name ("Full detail", "5,231 vertices"); percent < 0: it is shown (or failed).
  void levelDownload(int percent, const QString& name);
  /// Client: the host's level list changed (levels() may have changed).
  void levelsChanged();
  /// Hosting from a session file: its shape and edit history were restored and, when it had constraints, the lock
  /// was taken and they were set (emitted once, after hostingStarted()).
  void savedSessionRestored();
  /// editLog() changed (somebody's stroke, undo or redo).
  void editLogChanged();
  /// Another user's presence arrived (author = its peer id).
  void presenceReceived(const sc::session::Presence& presence);

 protected:
  explicit SessionController(QObject* parent);

  void changeState(State next);
  /// Enters Failed with `message` (once; not after Left), stops the session and emits failed().
  void fail(const QString& message);
  /// Stores and pushes down a new level / frame.
  void showLevel(spectral::SharedDisplayLevel level);
  void showFrame(spectral::DisplayFrame frame);
  /// The session's lock changed: (re)sends constraints when it was granted, ends a drag when it was lost.
  void onLockChanged();
  [[nodiscard]] bool leaving() const { return m_leaving; }
  /// cancel() took effect (see cancelledByUser()).
  void markCancelledByUser() { m_cancelledByUser = true; }
  void setLevelTarget(std::uint32_t target) { m_levelTarget = target; }
  [[nodiscard]] ConstraintEditor& editor() { return m_editor; }
  [[nodiscard]] const ConstraintEditor& editor() const { return m_editor; }

  /// This user's lock state machine (nullptr before there is one).
  [[nodiscard]] virtual const session::LockClient* lockClient() const = 0;
  /// Releases the lock through the session.
  virtual bool release() = 0;
  /// Stops the session object (host: shutdown; client: leave) and any preparation; called by leave() and fail().
  virtual void stop() = 0;

 private:
  State m_state = State::Idle;
  QString m_errorText;
  bool m_leaving = false;
  bool m_cancelledByUser = false;
  std::uint32_t m_levelTarget = 0;
  spectral::SharedDisplayLevel m_level;
  spectral::DisplayFrame m_frame;
  ConstraintEditor m_editor{*this};
  std::uint64_t m_refusalsShown = 0;  ///< the serial of the last refusal told (LockClient::lastRefusal())
  QTimer* m_secondTimer = nullptr;
};

/// Human-readable state, for status texts.
QString toString(SessionController::State state);

}  // namespace sc::app
