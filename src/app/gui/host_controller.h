#pragma once
// HostController: this instance hosts (SessionController's host role). It prepares the model on a worker thread
// (HostPreparation: mesh or saved session, basis, the full level built once), then owns a SessionHost whose own
// user is peer 1. Its display is the full level (K = quantizeBasis(H), shared with the view; the SessionHost keeps the
// double H its deformer needs), pushed down once, and one DisplayFrame{frame, float(Z)} per new frame.
// A host started from a session file restores the file's shape once live (savedSessionRestored()).
//
// Lifecycle: Idle --host()--> Preparing --> Live --leave()--> Left; failures (unreadable mesh, basis, cancel())
// --> Failed; a busy TCP port --> Failed inside host(), before any preparation (port_reservation.h). The destructor
// cancels and joins a running preparation (it waits for a running mesh load; the eigensolve stops at its next progress
// callback) and shuts a live host down (Leave to every peer is queued, not guaranteed to be written).

#include "app/gui/port_reservation.h"
#include "app/gui/session_controller.h"
#include "session/engine/edit_history.h"
#include "session/net/relay_publisher.h"

#include <memory>
#include <thread>

namespace sc::session {
class SessionHost;
struct HostModel;
struct HostEngineCounters;
}  // namespace sc::session

namespace sc::app {

class HostPreparation;
struct PreparedHost;

class HostController final : public SessionController {
  Q_OBJECT
  Q_DISABLE_COPY_MOVE(HostController)

 public:
  explicit HostController(QObject* parent = nullptr);
  ~HostController() override;

  /// Starts hosting: holds settings.port (`port` when it holds it, else a PortReservation taken here), loads the
  /// mesh and computes its basis on a worker thread (progress() with percent 0..100), then starts a SessionHost on
  /// that port (hostingStarted(port)). False (nothing started) unless state() is Idle; false too when the port is
  /// busy: state Failed and failed() naming the port, emitted inside host(), no preparation started.
  bool host(const HostSettings& settings, PortReservation port = {});
  /// Whether host() started the preparation on its worker (false before host() and after a busy port).
  [[nodiscard]] bool preparationStarted() const { return m_preparation != nullptr; }

  [[nodiscard]] Role role() const override { return Role::Host; }
  void cancel() override;
  [[nodiscard]] quint16 tcpPort() const override;
  [[nodiscard]] session::PeerId selfId() const override;
  bool requestLock() override;
  [[nodiscard]] std::vector<session::PeerId> lockHolders() const override;
  [[nodiscard]] std::vector<session::PeerId> lockQueue() const override;
  bool kick(session::PeerId peer) override;
  bool forceReleaseLock(session::PeerId holder = session::kNoPeer) override;
  [[nodiscard]] const model::SessionFile* savedSession() const override { return m_saved.get(); }
  [[nodiscard]] session::EditLog editLog() const override;
  bool requestEdit(session::EditAction action) override;
  /// Every step of the session's edit history (authors' names, ΔZ, undone or not), oldest first: what a saved
  /// session keeps. Empty when not live.
  [[nodiscard]] std::vector<session::EditStep> editSteps() const;
  /// What host() was given (the password forgotten once the host started).
  [[nodiscard]] const HostSettings& settings() const { return m_settings; }
  /// The deformer's exact Z (m by 3, double; the displayed frame is its float copy).
  [[nodiscard]] Eigen::MatrixXd coefficients() const override;
  [[nodiscard]] std::vector<LevelChoice> levels() const override;
  [[nodiscard]] session::PeerList peers() const override;
  [[nodiscard]] std::optional<session::StatsReport> stats(session::PeerId peer) const override;
  [[nodiscard]] double sentKbps(session::PeerId peer) const override;
  [[nodiscard]] QByteArray hostFingerprint() const override;
  /// With settings().relay, once live and connected: the viewers through NATS as one aggregate.
  [[nodiscard]] std::optional<session::RelayAudienceSummary> relayAudience() const override;
  /// The relay publisher (null unless relaying): its counters, for diagnostics and tests.
  [[nodiscard]] const session::RelayPublisher* relay() const { return m_relay; }
  void sendPresence(const session::Presence& presence) override;

  // --- the host's own figures (diagnostics and tests)
  /// What the host accepted, refused and sent so far (zeros before it started).
  [[nodiscard]] session::HostEngineCounters counters() const;
  /// The number of the latest frame produced (0 before any).
  [[nodiscard]] std::uint32_t currentFrame() const;
  /// The deformer's mode (a saved session's, else the default).
  [[nodiscard]] spectral::DeformationMode deformationMode() const;

 protected:
  [[nodiscard]] const session::LockClient* lockClient() const override;
  bool release() override;
  void stop() override;
  /// A host displays the full level: a displayed id is the full id (ids out of range dropped), lying at its row of V.
  [[nodiscard]] spectral::LocatedFullVertices fullVertices(const spectral::DisplayVertexIds& displayed) const override;
  [[nodiscard]] spectral::DisplayVertexIds displayedVertices(const spectral::LocatedFullVertices& full) const override;
  bool sendConstraints(const spectral::FullVertexIds& handle, const spectral::FullVertexIds& anchors) override;
  bool sendPose(const spectral::HandleTransform& pose) override;
  bool endStroke() override;

 private:
  void finishPreparation(const std::shared_ptr<PreparedHost>& prepared);
  void restoreSavedSession();
  /// Starts the relay publisher of settings().relay on the live host: the broker is connected on a thread of its own
  /// (up to its 2 s timeout when nobody answers; the window stays live), then finishRelay() starts the publisher
  /// here; failed() says why it could not (hosting goes on without it).
  void startRelay();
  void finishRelay(session::RelayBrokerLink link, const session::RelayPublisherOptions& options);
  void onFrame();

  HostSettings m_settings;
  std::unique_ptr<HostPreparation> m_preparation;
  PortReservation m_port;  ///< settings.port, held while preparing
  std::shared_ptr<const session::HostModel> m_model;
  std::shared_ptr<const model::SessionFile> m_saved;  ///< the session file it was started from
  session::SessionHost* m_host = nullptr;
  session::RelayPublisher* m_relay = nullptr;  ///< child of this, deleted before m_host
  std::thread m_relayConnect;                  ///< connectToBroker() for startRelay(); the destructor joins it
};

}  // namespace sc::app
