#pragma once
// ClientController: this instance joined a session (SessionController's client role). It owns a SessionClient
// (and its distortion meter) and passes the client's frame path straight down: the SessionClient's shared level
// (displayLevelChanged) and frames (frameUpdated) become this controller's displayLevelChanged() and
// frameChanged(), with no copy of the level here. Displayed ids map to full-resolution ids through the level's
// P (spectral::locateFullVertices), and back on each new level (spectral::displayedVertices). Also: the resolution
// choices, the emulated network conditions, this client's own statistics and how the host's certificate was trusted
// (pinned fingerprint or trust on first use).
//
// Lifecycle: Idle --join()--> Connecting (TCP, TLS, handshake, model download; progress()) --> Live once the
// first level is displayed; the host leaving or going silent, a refusal or cancel() --> Failed.
// Joins are progressive (session::SessionClientOptions::progressive): Live on the host's smallest level, with the
// live deformation, while the requested level streams in (levelDownload(percent, "Full detail"), then
// levelDownload(-1) once it is shown; the same for a later resolution switch).

#include "app/gui/session_controller.h"

#include "session/engine/network_impairment.h"

#include <cstdint>
#include <optional>

namespace sc::session {
class SessionClient;
class DistortionMeter;
}  // namespace sc::session

namespace sc::app {

/// How this client's datagram channel stands (diagnostics and tests).
struct FrameReception {
  bool hasFrame = false;        ///< a frame was received or seeded
  std::uint32_t received = 0;   ///< the newest frame received
  std::uint32_t displayed = 0;  ///< the frame shown: received plus predicted ones
  bool predicts = false;        ///< lost frames are concealed by extrapolation
  int predictedFrames = 0;      ///< frames shown past `received` (0: a received frame is shown)
};

class ClientController final : public SessionController {
  Q_OBJECT
  Q_DISABLE_COPY_MOVE(ClientController)

 public:
  explicit ClientController(QObject* parent = nullptr);
  /// A joined client leaves (Leave to the host).
  ~ClientController() override;

  /// Joins a host: the SessionClient connects, authenticates and downloads its level (progress()). Live once the
  /// first level is displayed (meshChanged()). False (nothing started) unless state() is Idle.
  bool join(const JoinSettings& settings);

  [[nodiscard]] Role role() const override { return Role::Client; }
  /// While connecting: state Failed with failed("Cancelled.").
  void cancel() override;
  [[nodiscard]] session::PeerId selfId() const override;
  bool requestLock() override;
  [[nodiscard]] std::vector<session::PeerId> lockHolders() const override;
  /// Full, then, once the host's LevelList is complete, its levels with their exact vertex counts ("5,231
  /// vertices"); before that model::levelTargets(n) largest first, "≈ N vertices" (the host sends the closest).
  [[nodiscard]] std::vector<LevelChoice> levels() const override;
  /// Asks the host for another level; the current one (and the deformation, which lives in Z) stays until the new
  /// one is in, then meshChanged(). False when not live.
  bool setLevel(std::uint32_t target) override;
  /// Simulates `loss` (0..1, clamped), mean burst `burstLength` (≥ 1; 1 = Bernoulli, more = Gilbert–Elliott) and
  /// `delayMs` (≥ 0) on the datagrams received, live (datagrams held back by the previous setting are delivered at
  /// once), and a link rate of `rateMbit` Mbit/s (0: unlimited; datagrams and the TLS stream share it, see
  /// session::SessionClient "Link rate"). All zero removes the impairment. Emits networkConditionsChanged().
  bool setNetworkConditions(double loss, double burstLength, int delayMs, double rateMbit) override;
  [[nodiscard]] NetworkConditions networkConditions() const override;
  [[nodiscard]] session::PeerList peers() const override;
  [[nodiscard]] session::EditLog editLog() const override;
  bool requestEdit(session::EditAction action) override;
  /// Only this client's own figures (selfId()), from its receiver statistics and distortion meter.
  [[nodiscard]] std::optional<session::StatsReport> stats(session::PeerId peer) const override;
  [[nodiscard]] QByteArray hostFingerprint() const override;
  void sendPresence(const session::Presence& presence) override;
  [[nodiscard]] HostTrust hostTrust() const override;
  [[nodiscard]] bool fingerprintRefused() const override;
  [[nodiscard]] std::optional<JoinSettings> passwordRetry() const override;

  // --- the client's own figures (diagnostics and tests)
  /// The impairment the datagram channel applies now (nullopt: none).
  [[nodiscard]] std::optional<session::ImpairmentSettings> impairmentInEffect() const;
  [[nodiscard]] FrameReception reception() const;
  /// The join's requested level is still to come behind the smallest one shown (progressive join, issue 17 item 4).
  [[nodiscard]] bool levelPending() const;

 protected:
  [[nodiscard]] const session::LockClient* lockClient() const override;
  bool release() override;
  void stop() override;
  /// Through the displayed level's P: the dominant full-resolution vertex of each displayed one, and back (on a
  /// coarser level the nearest displayed vertices stand in: spectral/level_vertex_map.h).
  [[nodiscard]] spectral::LocatedFullVertices fullVertices(const spectral::DisplayVertexIds& displayed) const override;
  [[nodiscard]] spectral::DisplayVertexIds displayedVertices(const spectral::LocatedFullVertices& full) const override;
  bool sendConstraints(const spectral::FullVertexIds& handle, const spectral::FullVertexIds& anchors) override;
  bool sendPose(const spectral::HandleTransform& pose) override;
  bool endStroke() override;

 private:
  void connectClient();
  void onClientState();
  void onLevelReady();

  session::SessionClient* m_client = nullptr;
  session::DistortionMeter* m_meter = nullptr;
  std::optional<double> m_joinFraction;
  JoinSettings m_joinSettings;              ///< what join() was given, without the password (passwordRetry())
  HostTrust m_joinTrust = HostTrust::None;  ///< what an accepted certificate means (set by join())
};

}  // namespace sc::app
