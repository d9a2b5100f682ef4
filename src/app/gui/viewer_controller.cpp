#include "app/gui/viewer_controller.h"

#include "session/engine/distortion_probe.h"
#include "session/engine/relay_display.h"
#include "session/net/relay_level_fetcher.h"
#include "session/net/relay_viewer.h"
#include "session/wire/relay_level_list.h"

#include <QLocale>
#include <QMetaObject>

#include <cmath>
#include <cstdlib>
#include <utility>

namespace sc::app {

ViewerController::ViewerController(QObject* parent) : SessionController(parent) {}

ViewerController::~ViewerController() { stop(); }

bool ViewerController::watch(const WatchSettings& settings) {
  if (state() != State::Idle) return false;
  m_settings = settings;
  m_clock.start();
  changeState(State::Connecting);
  emit progress(0, tr("Connecting to %1").arg(settings.url));
  session::RelayViewerOptions options;
  options.nats.url = settings.url;
  options.nats.user = settings.user;
  options.nats.password = settings.password;
  options.nats.caFile = settings.caFile;
  options.nats.name = QStringLiteral("shapecast viewer");
  options.sessionId = settings.sessionId;
  if (!settings.pin.isEmpty()) options.pin = settings.pin;
  options.concealment = settings.concealment;
  m_viewer = std::make_unique<session::RelayViewer>(std::move(options));
  QString error;
  if (!m_viewer->start(&error)) {
    fail(tr("Cannot watch session %1: %2").arg(settings.sessionId, error));
    return false;
  }
  m_trust = settings.pin.isEmpty() ? HostTrust::FirstUse : HostTrust::Pinned;
  connect(m_viewer.get(), &session::RelayViewer::displayChanged, this, &ViewerController::onFrame);
  session::RelayLevelFetcherOptions fetch;
  fetch.sessionId = settings.sessionId;
  fetch.facts = m_viewer->receiver().facts();
  m_fetcher = std::make_unique<session::RelayLevelFetcher>(*m_viewer->connection(), fetch);
  if (!m_fetcher->start(&error)) {
    fail(tr("Cannot read the levels of session %1: %2").arg(settings.sessionId, error));
    return false;
  }
  connect(m_fetcher.get(), &session::RelayLevelFetcher::levelReady, this, &ViewerController::onLevel);
  connect(m_fetcher.get(), &session::RelayLevelFetcher::levelRefused, this, &ViewerController::onLevelRefused);
  if (std::optional<session::RelayLevelList> list = m_fetcher->readList(&error)) {
    m_list = std::make_unique<session::RelayLevelList>(std::move(*list));
  }
  const std::uint32_t n = m_viewer->receiver().facts().vertexCount;
  std::uint32_t wanted = settings.level;
  if (settings.levelFraction && *settings.levelFraction < 1.0) {
    wanted = static_cast<std::uint32_t>(std::lround(*settings.levelFraction * n));
  }
  setLevelTarget(wanted);
  emit progress(30, tr("Fetching the level from the relay"));
  // Nothing listed yet (the host is still publishing): the full model, which the fetcher waits for (listWait).
  m_fetcher->fetch(closestIndex(wanted).value_or(0));
  return true;
}

std::optional<std::uint8_t> ViewerController::closestIndex(std::uint32_t target) const {
  if (!m_list || m_list->levels.empty()) return std::nullopt;
  const std::uint32_t n = m_list->vertexCount;
  const std::uint32_t wanted = target == 0 || target >= n ? n : target;
  const session::RelayLevelEntry* best = nullptr;
  for (const session::RelayLevelEntry& entry : m_list->levels) {
    const auto distance = [wanted](std::uint32_t v) { return v > wanted ? v - wanted : wanted - v; };
    if (!best || distance(entry.vertexCount) < distance(best->vertexCount) ||
        (distance(entry.vertexCount) == distance(best->vertexCount) && entry.vertexCount > best->vertexCount)) {
      best = &entry;
    }
  }
  return best->index;
}

void ViewerController::onFrame() {
  if (!m_viewer || !m_viewer->display().hasFrame()) return;
  if (displayLevel()) showFrame(displayed());
  emit statsChanged();
}

spectral::DisplayFrame ViewerController::displayed() const {
  spectral::DisplayFrame shown;
  shown.frame = m_viewer->display().displayedFrame();
  shown.Z = m_viewer->display().display().cast<float>();
  return shown;
}

void ViewerController::onLevel(std::uint8_t index, const spectral::SharedDisplayLevel& level) {
  if (std::optional<session::RelayLevelList> list = m_fetcher->readList()) {
    m_list = std::make_unique<session::RelayLevelList>(std::move(*list));
  }
  m_shownIndex = index;
  showLevel(level);
  if (m_viewer) m_viewer->setLevel(level);  // distortion is measured at the level shown
  if (m_viewer && m_viewer->display().hasFrame()) showFrame(displayed());
  if (state() == State::Connecting) {
    emit progress(100, tr("Watching"));
    changeState(State::Live);
  }
  emit meshChanged();
  emit levelsChanged();
  emit peersChanged();
}

void ViewerController::onLevelRefused(std::uint8_t index, const QString& reason) {
  const QString text = tr("Level %1 from the relay was refused: %2").arg(index).arg(reason);
  if (state() == State::Connecting) {
    // Later: fail() stops the fetcher, which is emitting this signal.
    QMetaObject::invokeMethod(
        this, [this, text] { fail(text); }, Qt::QueuedConnection);
  } else {
    emit failed(text);  // the shown level stays
  }
}

void ViewerController::cancel() {
  if (state() != State::Connecting) return;
  markCancelledByUser();
  fail(tr("Cancelled."));
}

void ViewerController::stop() {
  m_fetcher.reset();  // joins a fetch in flight
  m_viewer.reset();
}

std::vector<LevelChoice> ViewerController::levels() const {
  if (!m_list) return {};
  const QLocale locale;
  std::vector<LevelChoice> out;
  for (const session::RelayLevelEntry& entry : m_list->levels) {
    const bool current = m_shownIndex == entry.index;
    if (entry.index == 0) {
      out.insert(out.begin(), {0, tr("Full — %1 vertices").arg(locale.toString(entry.vertexCount)), current});
    } else {
      out.push_back({entry.vertexCount, tr("%1 vertices").arg(locale.toString(entry.vertexCount)), current});
    }
  }
  return out;
}

bool ViewerController::setLevel(std::uint32_t target) {
  if (state() != State::Live || !m_fetcher) return false;
  const std::optional<std::uint8_t> index = closestIndex(target);
  if (!index) return false;
  setLevelTarget(target);
  if (*index != m_shownIndex) m_fetcher->fetch(*index);
  return true;
}

session::PeerList ViewerController::peers() const {
  session::PeerList list;
  if (!m_viewer) return list;
  session::PeerInfo self;
  self.peerId = kViewerSelf;
  self.name = tr("this viewer (NATS)");
  self.vertexCount = displayLevel() ? displayLevel()->vertexCount() : 0;
  list.peers.push_back(self);
  return list;
}

std::optional<session::StatsReport> ViewerController::stats(session::PeerId peer) const {
  if (peer != kViewerSelf || !m_viewer) return std::nullopt;
  const session::RelayViewerStats s = m_viewer->stats();
  session::StatsReport report;
  report.vertexCount = displayLevel() ? displayLevel()->vertexCount() : 0;
  report.framesApplied = static_cast<std::uint32_t>(s.applied);
  report.received = static_cast<std::uint64_t>(s.applied + s.stale);
  report.lost = static_cast<std::uint64_t>(s.lost);
  report.late = static_cast<std::uint64_t>(s.stale);
  report.dropped = static_cast<std::uint64_t>(s.badSignature + s.malformed + m_viewer->droppedPending());
  const double expected = static_cast<double>(s.applied + s.lost);
  report.lossFraction = expected > 0 ? static_cast<double>(s.lost) / expected : 0.0;
  const double seconds = static_cast<double>(m_clock.elapsed()) / 1000.0;
  report.framesPerSecond = seconds > 0 ? static_cast<double>(s.applied) / seconds : 0.0;
  report.latencyP50Ms = s.latencyP50Ms;
  report.latencyP99Ms = s.latencyP99Ms;
  const session::DistortionSummary& distortion = m_viewer->display().distortion();
  report.hdMaxPct = distortion.maxPct;
  report.hdMeanPct = distortion.meanPct;
  report.hdLastPct = distortion.lastPct;
  return report;
}

QByteArray ViewerController::hostFingerprint() const {
  return m_viewer ? m_viewer->receiver().fingerprint() : QByteArray();
}

std::optional<QString> ViewerController::readOnlyText() const {
  return tr("Watching %1 through NATS").arg(m_settings.sessionId);
}

Eigen::MatrixXd ViewerController::coefficients() const {
  return m_viewer ? m_viewer->receiver().coefficients() : Eigen::MatrixXd();
}

spectral::LocatedFullVertices ViewerController::fullVertices(const spectral::DisplayVertexIds& /*displayed*/) const {
  return {};
}

spectral::DisplayVertexIds ViewerController::displayedVertices(const spectral::LocatedFullVertices& /*full*/) const {
  return {};
}

}  // namespace sc::app
