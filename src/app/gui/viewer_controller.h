#pragma once
// ViewerController: this instance watches a session relayed through NATS (issue 18 item 2; SessionController's
// client role, read-only). It owns a RelayViewer (frames, keyframe, pinned facts: session/net/relay_viewer.h) and a
// RelayLevelFetcher (its level from the session's stream: session/net/relay_level_fetcher.h), never connects to the
// host and cannot edit: no lock, no constraints, no drags, no edits, no presence (readOnlyText() says so). The frame
// path is the client's: the fetched level (shared, immutable) becomes displayLevelChanged(), every applied relayed
// frame (exact f64 Z, shown as float; with WatchSettings::concealment Extrapolate, overdue frames predicted as the
// UDP client does, session/engine/relay_display.h) frameChanged(). Statistics: this viewer's own figures (frames
// applied, loss, latency from the host's stamp: meaningful on the host's machine only, and the distortion against the
// host's keyframes read back as exact references, measured at the shown level) as one StatsReport.
//
// Lifecycle: Idle --watch()--> Connecting (broker, facts, keyframe, then the level list and the level) --> Live once
// the first level is displayed; a refused level or facts --> Failed. Another level: setLevel(vertices) fetches the
// listed level closest to it; the current one stays until it is in.

#include "app/gui/session_controller.h"
#include "app/gui/watch_settings.h"
#include "spectral/display_level.h"

#include <QElapsedTimer>

#include <cstdint>
#include <memory>
#include <optional>

namespace sc::session {
class RelayViewer;
class RelayLevelFetcher;
struct RelayLevelList;
}  // namespace sc::session

namespace sc::app {

/// The peer id a viewer shows itself as (viewers have none in the session: they are not its members).
inline constexpr session::PeerId kViewerSelf = 0xFFFF;

class ViewerController final : public SessionController {
  Q_OBJECT
  Q_DISABLE_COPY_MOVE(ViewerController)

 public:
  explicit ViewerController(QObject* parent = nullptr);
  ~ViewerController() override;

  /// Connects to the broker, reads the facts (pinned or trusted on first use) and the keyframe, then fetches the
  /// level closest to settings.level / levelFraction. False (state Failed, failed() emitted) when the broker or the
  /// session cannot be read; true otherwise (Live once the level is in). Only from Idle.
  bool watch(const WatchSettings& settings);

  [[nodiscard]] Role role() const override { return Role::Client; }
  void cancel() override;
  [[nodiscard]] session::PeerId selfId() const override { return kViewerSelf; }
  bool requestLock() override { return false; }
  [[nodiscard]] std::vector<session::PeerId> lockHolders() const override { return {}; }
  /// "Full — N vertices" and the listed levels' exact vertex counts, from the signed level list.
  [[nodiscard]] std::vector<LevelChoice> levels() const override;
  /// Fetches the listed level closest to `target` vertices (0 = full). False when not live or nothing is listed.
  bool setLevel(std::uint32_t target) override;
  [[nodiscard]] session::PeerList peers() const override;
  [[nodiscard]] session::EditLog editLog() const override { return {}; }
  bool requestEdit(session::EditAction /*action*/) override { return false; }
  [[nodiscard]] std::optional<session::StatsReport> stats(session::PeerId peer) const override;
  [[nodiscard]] QByteArray hostFingerprint() const override;
  [[nodiscard]] HostTrust hostTrust() const override { return m_trust; }
  void sendPresence(const session::Presence& /*presence*/) override {}
  [[nodiscard]] std::optional<QString> readOnlyText() const override;

  /// The exact relayed coefficients (f64), m by 3; empty before the first frame.
  [[nodiscard]] Eigen::MatrixXd coefficients() const override;
  [[nodiscard]] const session::RelayViewer* viewer() const { return m_viewer.get(); }

 protected:
  [[nodiscard]] const session::LockClient* lockClient() const override { return nullptr; }
  bool release() override { return false; }
  void stop() override;
  [[nodiscard]] spectral::LocatedFullVertices fullVertices(const spectral::DisplayVertexIds& displayed) const override;
  [[nodiscard]] spectral::DisplayVertexIds displayedVertices(const spectral::LocatedFullVertices& full) const override;
  bool sendConstraints(const spectral::FullVertexIds& /*handle*/, const spectral::FullVertexIds& /*anchors*/) override {
    return false;
  }
  bool sendPose(const spectral::HandleTransform& /*pose*/) override { return false; }
  bool endStroke() override { return false; }

 private:
  void onFrame();
  /// What the viewer's display shows now (the newest frame, or a prediction with Concealment::Extrapolate).
  [[nodiscard]] spectral::DisplayFrame displayed() const;
  void onLevel(std::uint8_t index, const spectral::SharedDisplayLevel& level);
  void onLevelRefused(std::uint8_t index, const QString& reason);
  [[nodiscard]] std::optional<std::uint8_t> closestIndex(std::uint32_t target) const;

  WatchSettings m_settings;
  std::unique_ptr<session::RelayViewer> m_viewer;
  std::unique_ptr<session::RelayLevelFetcher> m_fetcher;
  std::unique_ptr<session::RelayLevelList> m_list;
  std::optional<std::uint8_t> m_shownIndex;
  HostTrust m_trust = HostTrust::None;
  QElapsedTimer m_clock;  ///< since watch(): frames per second
};

}  // namespace sc::app
