#include "app/gui/session_docks.h"

#include "app/gui/peers_dock.h"
#include "app/gui/relay_audience_view.h"
#include "app/gui/repaint_batch.h"
#include "app/gui/session_controller.h"
#include "app/gui/statistics_dock.h"
#include "model/peer_table_model.h"
#include "model/statistics_model.h"
#include "session/net/session_host.h"  // kHostPeer

#include <QMainWindow>

#include <algorithm>

// A host relaying through NATS adds one Peers row and one Statistics section for all its viewers, however many
// (relay_audience_view.h).

namespace sc::app {

SessionDocks::SessionDocks(QMainWindow* window) : QObject(window) {
  m_peerModel = new model::PeerTableModel(this);
  m_peersDock = new PeersDock(m_peerModel, window);
  m_statisticsDock = new StatisticsDock(nullptr, window);
  window->addDockWidget(Qt::RightDockWidgetArea, m_peersDock);
  window->addDockWidget(Qt::RightDockWidgetArea, m_statisticsDock);
  connect(m_peersDock, &PeersDock::currentPeerChanged, this, &SessionDocks::showStatisticsOf);
  m_repaint = new RepaintBatch(this);
  m_repaint->add(m_peersDock);
  m_repaint->add(m_statisticsDock);
}

SessionDocks::~SessionDocks() = default;

void SessionDocks::bind(SessionController* controller) {
  if (m_controller) m_controller->disconnect(this);
  m_controller = controller;
  m_peerModel->setPeers({});
  m_statisticsDock->setModel(nullptr);
  m_statisticsDock->setRelayAudience({});
  for (auto& [peer, statistics] : m_statistics) delete statistics;
  m_statistics.clear();
  m_shownPeer = 0;
  m_clock.start();
  if (controller == nullptr) return;
  connect(controller, &SessionController::peersChanged, this, &SessionDocks::refreshPeers);
  connect(controller, &SessionController::lockChanged, this, &SessionDocks::refreshPeers);
  connect(controller, &SessionController::meshChanged, this, &SessionDocks::refreshPeers);
  connect(controller, &SessionController::statsChanged, this, [this] {
    m_repaint->hold();  // the charts settle over a few passes: one repaint of both docks after them
    appendStatistics();
    refreshPeers();
  });
}

model::StatisticsModel* SessionDocks::statisticsOf(quint32 peer) const {
  const auto it = m_statistics.find(peer);
  return it == m_statistics.end() ? nullptr : it->second;
}

void SessionDocks::refreshPeers() {
  if (!m_controller) return;
  const session::PeerList peers = m_controller->peers();
  const std::vector<session::PeerId> holders = m_controller->lockHolders();
  const std::vector<session::PeerId> queue = m_controller->lockQueue();
  std::uint32_t fullVertices = 0;
  std::vector<model::PeerRow> rows;
  for (const session::PeerInfo& peer : peers.peers) {
    model::PeerRow row;
    row.peerId = peer.peerId;
    row.name = peer.name;
    row.vertexCount = peer.vertexCount;
    row.isHost = peer.peerId == session::kHostPeer;
    row.isSelf = peer.peerId == m_controller->selfId();
    if (row.isHost) fullVertices = peer.vertexCount;
    const auto waiting = std::find(queue.begin(), queue.end(), peer.peerId);
    if (std::find(holders.begin(), holders.end(), peer.peerId) != holders.end()) {
      row.lock = model::PeerRow::Lock::Holder;
    } else if (waiting != queue.end()) {
      row.lock = model::PeerRow::Lock::Queued;
      row.queuePosition = static_cast<int>(waiting - queue.begin()) + 1;
    }
    if (const std::optional<session::StatsReport> report = m_controller->stats(peer.peerId)) {
      row.hasStats = true;
      row.lossPct = 100.0 * report->lossFraction;
      row.latencyP99Ms = report->latencyP99Ms;
      row.kbpsIn = report->payloadKbpsIn;
      row.hdMaxPct = report->hdMaxPct;
    }
    rows.push_back(std::move(row));
  }
  // The viewers through NATS (a relaying host): one aggregate row and one Statistics section, however many.
  const std::optional<session::RelayAudienceSummary> audience = m_controller->relayAudience();
  if (audience) rows.push_back(relayAudienceRow(*audience));
  m_statisticsDock->setRelayAudience(audience ? relayAudienceText(*audience) : QString());
  if (fullVertices > 0) m_peerModel->setFullVertexCount(fullVertices);
  m_peerModel->setPeers(std::move(rows));
}

void SessionDocks::appendStatistics() {
  if (!m_controller) return;
  const double t = static_cast<double>(m_clock.elapsed()) / 1000.0;
  for (const session::PeerInfo& peer : m_controller->peers().peers) {
    const std::optional<session::StatsReport> report = m_controller->stats(peer.peerId);
    if (!report) continue;
    model::StatisticsModel*& statistics = m_statistics[peer.peerId];
    if (statistics == nullptr) {
      statistics = new model::StatisticsModel(this);
      statistics->setTitle(peer.name);
    }
    model::StatsSample sample;
    sample.t = t;
    sample.hdPct = report->hdLastPct;
    sample.lossPct = 100.0 * report->lossFraction;
    sample.kbpsIn = report->payloadKbpsIn;
    sample.kbpsOut = m_controller->sentKbps(peer.peerId);
    sample.fps = report->framesPerSecond;
    sample.latencyMs = report->latencyP99Ms;
    statistics->append(sample);
    if (m_shownPeer == 0) showStatisticsOf(peer.peerId);  // the first peer with figures until the user picks one
  }
}

void SessionDocks::showStatisticsOf(quint32 peer) {
  model::StatisticsModel* statistics = statisticsOf(peer);
  if (statistics == nullptr) return;
  m_shownPeer = peer;
  m_statisticsDock->setModel(statistics);
}

}  // namespace sc::app
