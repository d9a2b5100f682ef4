#pragma once
// SessionController: the desktop app's glue between the window and a session (src/session). It owns either a
// SessionHost (this instance hosts; its own user is peer 1) or a SessionClient (this instance joined), and gives the
// window one uniform API whichever it is: lock, constraints, drags, displayed mesh and positions, levels, peers and
// statistics, errors as readable text. No protocol or math decisions live here: they are the session's and the
// spectral module's; this class only adapts them (style.md item 1, "app is composition").
//
// Lifecycle (state()):
//   Idle --host()--> Preparing (mesh load + basis on a worker thread; progress(), cancel()) --> Live
//   Idle --join()--> Connecting (TCP, handshake, model download; progress()) --> Live
//   Live --leave()--> Left;  any --error--> Failed (failed(text) emitted once, with readable text).
//   A controller is used for one session: after Left or Failed, make a new one to host or join again.
//
// Threading: lives on the GUI thread. The only worker is the host's preparation thread (HostPreparation: loadMesh,
// basisForMesh, the full-resolution level); it reports back through queued calls and is cancelled and joined by
// cancel(), by leave() and by the destructor (which therefore waits for a running mesh load; the eigensolve stops at
// its next progress callback). Nothing blocks the GUI thread for longer than one reconstruction of the displayed level.
//
// Errors never throw: every failure (unreadable mesh, basis failure, port in use, unreachable host, wrong password,
// version mismatch (the host's Refused text), host gone or silent, a host certificate that does not match the
// pinned or remembered fingerprint: fingerprintRefused()) becomes failed(QString).

#include "session/wire/control_messages.h"
#include "session/wire/lock_messages.h"
#include "session/engine/network_impairment.h"

#include <Eigen/Core>
#include <QObject>
#include <QString>

#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <vector>

class QTimer;

namespace sc::session {
class SessionHost;
class SessionClient;
class DistortionMeter;
struct HostModel;
}  // namespace sc::session

namespace sc::model {
struct SessionFile;
}

namespace sc::spectral {
struct ResolutionLevel;
}

namespace sc::app {

class HostPreparation;
struct PreparedHost;

/// What host() needs. Validation of user input happens in the dialog; host() fails with failed() on what only
/// the attempt can reveal (unreadable mesh, port in use).
struct HostSettings {
  QString meshPath;                 ///< OFF, OBJ, PLY or STL
  quint16 port = 47100;             ///< TCP port; 0 = any free port (see tcpPort())
  std::optional<QString> password;  ///< none: open session
  int m = 100;                      ///< number of frequencies, 1 ≤ m < #V (clamped to #V − 1)
  QString name = QStringLiteral("host");
  bool useBasisCache = true;  ///< look up / store the basis in model::basisCacheDirectory()
};

/// What join() needs.
struct JoinSettings {
  QString host = QStringLiteral("127.0.0.1");
  quint16 port = 47100;
  std::optional<QString> password;
  QString name;
  std::uint32_t level = 0;  ///< wanted display vertices; 0 = full resolution
  /// Overrides `level`: this fraction of the host's vertex count (e.g. 0.2 for "20 %"); ≥ 1 = full resolution.
  std::optional<double> levelFraction;
  /// Emulated network conditions on receive from the start (see SessionController::setNetworkConditions).
  std::optional<session::ImpairmentSettings> impairment;
  /// Pinned SHA-256 of the host's certificate (session::parseFingerprint); empty: trust on first use, as
  /// `shapecast-cli join` (the first fingerprint seen for host:port is remembered, a changed one is refused).
  QByteArray fingerprint;
  /// The known-hosts store (session::KnownHosts); empty: the application's QSettings (tests give an INI file).
  QString knownHostsFile;
};

/// How the host's certificate was trusted when joining (SessionController::hostTrust()).
enum class HostTrust {
  None,      ///< not joined (or hosting), or refused
  Pinned,    ///< matched the fingerprint the user entered
  Known,     ///< matched the fingerprint remembered from an earlier join of this host:port
  FirstUse,  ///< first join of this host:port: remembered now; the user should compare it with the host's once
};

/// Emulated network conditions of a client, as the Network conditions dock edits them.
struct NetworkConditions {
  double loss = 0.0;         ///< stationary loss probability, 0..1
  double burstLength = 1.0;  ///< mean burst of consecutive losses in datagrams; 1 = independent (Bernoulli) loss
  int delayMs = 0;           ///< fixed one-way delay added on receive
};

/// The deformer state the host's own user set: the constraint set (full-resolution vertex ids, which are the
/// displayed ids on a host; anchors exclude the handle) and the handle's pose about its rest centroid. Solving
/// it again reproduces the shape exactly in linear mode (the solve is a function of constraints and pose) and
/// up to the rigid iterations' warm start in rigid mode. What undo/redo of a committed drag restores.
struct HostDeformation {
  std::vector<int> handle;
  std::vector<int> anchors;
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();

  friend bool operator==(const HostDeformation&, const HostDeformation&) = default;
};

/// One entry of the resolution selector.
struct LevelChoice {
  std::uint32_t target = 0;  ///< what setLevel() takes (0 = full resolution)
  QString label;             ///< "Full — N vertices", then "N vertices" (exact) or "≈ N vertices"
  bool current = false;      ///< the displayed level (exact list) or the target last asked for
};

class SessionController final : public QObject {
  Q_OBJECT
  Q_DISABLE_COPY_MOVE(SessionController)

 public:
  enum class Role { None, Host, Client };
  Q_ENUM(Role)
  enum class State { Idle, Preparing, Connecting, Live, Left, Failed };
  Q_ENUM(State)

  explicit SessionController(QObject* parent = nullptr);
  /// Cancels and joins a running preparation; a live host shuts down (Leave to every peer is queued, not
  /// guaranteed to be written), a live client leaves.
  ~SessionController() override;

  // --- starting and ending
  /// Starts hosting: loads the mesh and computes its basis on a worker thread (progress() with percent 0..100),
  /// then starts a SessionHost (hostingStarted(port)). False (nothing started) unless state() is Idle.
  bool host(const HostSettings& settings);
  /// Joins a host: the SessionClient connects, authenticates and downloads its level (progress()). Live once the
  /// first level is displayed (meshChanged()). False (nothing started) unless state() is Idle.
  bool join(const JoinSettings& settings);
  /// Cancels a running preparation (host) or connection (client): state Failed with failed("Cancelled").
  void cancel();
  /// Leaves the session (client: Leave to the host; host: Leave to every peer). State Left. No-op when not
  /// Preparing, Connecting or Live.
  void leave();

  [[nodiscard]] Role role() const { return m_role; }
  [[nodiscard]] State state() const { return m_state; }
  [[nodiscard]] const QString& errorText() const { return m_errorText; }
  /// The host's TCP port (0 unless hosting and live).
  [[nodiscard]] quint16 tcpPort() const;
  /// This user's peer id: 1 on a host, the Welcome's id on a client, kNoPeer before.
  [[nodiscard]] session::PeerId selfId() const;

  // --- lock
  /// Asks for the edit lock (false when already asked for, held, or not live).
  bool requestLock();
  /// Releases (or cancels the request for) the lock; ends a drag in progress.
  bool releaseLock();
  /// True when this user holds the lock (drags would be accepted).
  [[nodiscard]] bool canDrag() const;
  /// True while the lock is requested, queued or held by this user.
  [[nodiscard]] bool lockWanted() const;
  /// Who holds the lock, for the UI: "You hold the lock", "Lock held by NAME", "Lock free", plus the queue
  /// position ("you are 2nd in the queue") or "requesting…" while this user waits. Empty when not live.
  [[nodiscard]] QString lockText() const;
  [[nodiscard]] session::PeerId lockHolder() const;
  /// Peers waiting for the lock, first in line first (host: the arbiter's queue; client: unknown, empty).
  [[nodiscard]] std::vector<session::PeerId> lockQueue() const;

  // --- constraints and drags (ids are vertex ids of the displayed mesh)
  /// The handle group (displayed vertex ids). Sent with the anchors to the host at once when this user holds the
  /// lock, otherwise when the lock is granted. On a client at a low level each displayed vertex is mapped to the
  /// full-resolution vertex with the largest barycentric weight in its row of P (duplicates removed). Ids out of
  /// range are dropped. Returns true when the constraints were sent now.
  bool setHandle(std::vector<int> displayedIds);
  /// The anchors (displayed vertex ids), as setHandle().
  bool setAnchors(std::vector<int> displayedIds);
  [[nodiscard]] const std::vector<int>& handle() const { return m_handle; }
  [[nodiscard]] const std::vector<int>& anchors() const { return m_anchors; }
  /// Starts a drag of the handle: false without the lock or without a handle.
  bool beginDrag();
  /// The handle's pose since beginDrag(), as MeshViewport::dragMoved gives it: x ↦ R(x − c₀) + c₀ + t, c₀ the
  /// handle's centroid at the start of this drag. Composed with the pose the previous drags (same constraints)
  /// left, (R₀, t₀), into the deformer's pose about the rest centroid: (R·R₀, t₀ + t); exact when the handle sits
  /// on its target (c₀ = c_rest + t₀), which the soft constraints meet up to the handle residual. False outside
  /// beginDrag()/endDrag() or when refused (lock lost meanwhile).
  bool dragTo(const Eigen::Vector3d& translation, const Eigen::Matrix3d& rotation);
  /// Handle and anchors at once (one constraints message instead of two); as setHandle().
  bool setSelection(std::vector<int> handle, std::vector<int> anchors);
  /// Ends the drag (the shape stays where the last pose put it).
  void endDrag();
  [[nodiscard]] bool dragging() const { return m_dragging; }
  /// Host only: the constraints this user last sent and the pose its drags left (nullopt on a client, or
  /// before this user's constraints reached the deformer). Constraints or drags of clients are not included.
  [[nodiscard]] std::optional<HostDeformation> hostDeformation() const;
  /// Host started from a session file (host() with a `.shapecast` file as meshPath): that file's content, else
  /// nullptr. Its current state is restored once live (savedSessionRestored()).
  [[nodiscard]] const model::SessionFile* savedSession() const { return m_saved.get(); }
  /// Host only, as the lock holder and outside a drag: sets `state`'s constraints and solves its pose again, so
  /// that everyone sees that shape (a new frame); handle() and anchors() become the state's and the next drag
  /// starts from its pose. False (nothing changed) on a client, without the lock, during a drag, with an empty
  /// handle or ids the deformer refuses.
  bool restoreHostDeformation(const HostDeformation& state);

  // --- what to display
  /// The current level's rest mesh: #V' by 3 positions X̂' and #F' by 3 faces (empty before the first level).
  [[nodiscard]] const Eigen::MatrixXd& displayRestPositions() const;
  [[nodiscard]] const Eigen::MatrixXi& displayFaces() const;
  /// Current display positions, 3·#V' floats interleaved xyz: X̂' + K·Z for Z = positionsCoefficients() (client:
  /// SessionClient::positions(); host: X̂ + H·Z of the full level). Empty before the first level. Reconstructed on
  /// the first call after positionsChanged() (O(#V'·m)), so a view that reconstructs from level()->K and
  /// positionsCoefficients() itself (MeshViewport::setCoefficients) does not pay for it twice.
  [[nodiscard]] std::span<const float> positions() const;
  /// Current coefficients Z (m by 3): the host's latest frame, or the client's current frame (empty before).
  [[nodiscard]] Eigen::MatrixXd coefficients() const;
  /// The Z (m by 3, float32) of positions(): what a view reconstructing with level()->K shows; empty before the
  /// first level.
  [[nodiscard]] Eigen::MatrixXf positionsCoefficients() const;
  /// The displayed level (full level on a host), nullptr before the first.
  [[nodiscard]] const spectral::ResolutionLevel* level() const;
  /// Time of the latest reconstruction of positions() in milliseconds: the last positions() call that reconstructed
  /// (client: SessionClient::reconstructionMs()); 0 before the first.
  [[nodiscard]] double reconstructionMs() const;

  // --- levels
  /// The resolution choices: full, then, once the host's LevelList is complete, its levels with their exact
  /// vertex counts ("5,231 vertices"), before that model::levelTargets(n) largest first, labelled "≈ N vertices"
  /// (the host sends the ladder level closest to N). A host displays only the full level.
  [[nodiscard]] std::vector<LevelChoice> levels() const;
  /// The target last asked for (0 = full).
  [[nodiscard]] std::uint32_t levelTarget() const { return m_levelTarget; }
  /// Client: asks the host for another level; the current one (and the deformation, which lives in Z) stays
  /// until the new one is in, then meshChanged(). False on a host or when not live.
  bool setLevel(std::uint32_t target);

  // --- emulated network conditions (client)
  /// Client: simulates `loss` (0..1, clamped), mean burst `burstLength` (≥ 1; 1 = Bernoulli, more = Gilbert–
  /// Elliott) and `delayMs` (≥ 0) on the datagrams this client receives, live (datagrams held back by the previous
  /// setting are delivered at once: ClientDatagramChannel::setImpairment). loss 0 and delay 0 remove the
  /// impairment. Emits networkConditionsChanged(). False (nothing changed) on a host or before join().
  bool setNetworkConditions(double loss, double burstLength, int delayMs);
  /// The client's current conditions (zeros: none); also on a host (always zeros).
  [[nodiscard]] NetworkConditions networkConditions() const;

  // --- peers and statistics
  [[nodiscard]] session::PeerList peers() const;
  /// A peer's latest figures: on a host every client's StatsReport; on a client only its own (selfId()),
  /// assembled from its receiver statistics and distortion meter. nullopt when unknown.
  [[nodiscard]] std::optional<session::StatsReport> stats(session::PeerId peer) const;

  // --- host identity (docs/security.md)
  /// SHA-256 of the host's TLS certificate (session::kFingerprintSize bytes): on a host its own (once live); on a
  /// client the one the host showed (once the TLS handshake ended, also when it was refused). Empty otherwise.
  [[nodiscard]] QByteArray hostFingerprint() const;
  /// Client: how that fingerprint was trusted (None until the certificate was accepted, and on a host).
  [[nodiscard]] HostTrust hostTrust() const;
  /// Client: true when the join failed because the host's certificate did not match the pinned fingerprint or
  /// the one remembered for that host:port (the failed() text names both).
  [[nodiscard]] bool fingerprintRefused() const;

  /// The underlying session objects (nullptr when not of that role or not started), for tests and docks.
  [[nodiscard]] session::SessionHost* sessionHost() const { return m_host; }
  [[nodiscard]] session::SessionClient* sessionClient() const { return m_client; }

 signals:
  void stateChanged(sc::app::SessionController::State state);
  /// The displayed mesh (level) was replaced: re-read displayRestPositions()/displayFaces()/positions().
  void meshChanged();
  /// positions() changed (same mesh).
  void positionsChanged();
  void lockChanged();
  void peersChanged();
  void statsChanged();
  /// A readable error; state() is Failed (or, for a rejected level, stays Live).
  void failed(const QString& message);
  void hostingStarted(quint16 port);
  /// setNetworkConditions() changed the client's emulated conditions.
  void networkConditionsChanged();
  /// Long work: percent 0..100 and what is being done.
  void progress(int percent, const QString& what);
  /// Client: the host's level list changed (levels() may have changed).
  void levelsChanged();
  /// Hosting from a session file: the lock was taken and the file's current state restored (emitted once, after
  /// hostingStarted(); DragHistory rebuilds the saved undo history on it).
  void savedSessionRestored();

 private:
  void changeState(State next);
  void fail(const QString& message);
  void finishPreparation(const std::shared_ptr<PreparedHost>& prepared);
  void onHostFrame();
  void restoreSavedSession();
  void onClientState();
  void onClientLevel();
  void onLockChanged();
  bool sendConstraints();
  [[nodiscard]] std::vector<int> toFullIds(const std::vector<int>& displayed) const;
  [[nodiscard]] const spectral::ResolutionLevel* clientLevel() const;
  /// out = X̂' + K·Z of `level` from the interleaved `rest`; returns the time taken in milliseconds.
  static double timedReconstruction(const spectral::ResolutionLevel& level, std::span<const float> rest,
                                    const Eigen::MatrixXd& Z, std::vector<float>& out);

  Role m_role = Role::None;
  State m_state = State::Idle;
  QString m_errorText;
  bool m_leaving = false;

  // host
  session::SessionHost* m_host = nullptr;
  std::shared_ptr<const session::HostModel> m_model;
  std::unique_ptr<spectral::ResolutionLevel> m_fullLevel;  ///< host display: K = float(H)
  std::vector<float> m_rest;                               ///< host: X̂ interleaved
  mutable std::vector<float> m_hostPositions;  ///< a cache: X̂ + H·m_lastZ once m_hostPositionsStale is false
  mutable bool m_hostPositionsStale = false;
  Eigen::MatrixXd m_lastZ;
  HostSettings m_hostSettings;
  std::optional<double> m_joinFraction;
  HostTrust m_joinTrust = HostTrust::None;  ///< client: what an accepted certificate means (set by join())
  std::unique_ptr<HostPreparation> m_preparation;
  std::shared_ptr<const model::SessionFile> m_saved;  ///< host: the session file it was started from

  // client
  session::SessionClient* m_client = nullptr;
  session::DistortionMeter* m_meter = nullptr;
  Eigen::MatrixXd m_clientRestV;  ///< X̂' of the displayed client level (double, for the view)

  // shared
  std::vector<int> m_handle;
  std::vector<int> m_anchors;
  std::vector<int> m_sentHandle;  ///< host: the full ids of the constraints last sent
  std::vector<int> m_sentAnchors;
  bool m_constraintsSent = false;
  bool m_hadLock = false;
  bool m_dragging = false;
  Eigen::Matrix3d m_baseRotation = Eigen::Matrix3d::Identity();  ///< pose left by the previous drags (R₀, t₀)
  Eigen::Vector3d m_baseTranslation = Eigen::Vector3d::Zero();
  Eigen::Matrix3d m_lastRotation = Eigen::Matrix3d::Identity();  ///< the last pose sent
  Eigen::Vector3d m_lastTranslation = Eigen::Vector3d::Zero();
  std::uint32_t m_levelTarget = 0;
  mutable double m_reconstructionMs = 0.0;
  QTimer* m_secondTimer = nullptr;
};

/// Human-readable state, for status texts.
QString toString(SessionController::State state);

}  // namespace sc::app
