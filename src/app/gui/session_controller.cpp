// SessionController, part 1: lifecycle (state, failure, cancel, leave), identity, what to display, levels and
// peers. The host side lives in session_controller_host.cpp, the client side in session_controller_client.cpp,
// lock, constraints and drags in session_controller_editing.cpp.
#include "app/gui/session_controller.h"

#include "app/gui/host_preparation.h"
#include "model/mesh_decimation.h"
#include "session/engine/host_model.h"
#include "session/net/session_client.h"
#include "session/net/session_host.h"
#include "spectral/reconstruction_kernel.h"
#include "spectral/resolution_level.h"

#include <QLocale>
#include <QTimer>

#include <chrono>

namespace sc::app {

namespace {

const Eigen::MatrixXd kEmptyV;
const Eigen::MatrixXi kEmptyF;

}  // namespace

QString toString(SessionController::State state) {
  switch (state) {
    case SessionController::State::Idle:
      return QStringLiteral("not in a session");
    case SessionController::State::Preparing:
      return QStringLiteral("preparing");
    case SessionController::State::Connecting:
      return QStringLiteral("connecting");
    case SessionController::State::Live:
      return QStringLiteral("live");
    case SessionController::State::Left:
      return QStringLiteral("left");
    case SessionController::State::Failed:
      return QStringLiteral("failed");
  }
  return {};
}

SessionController::SessionController(QObject* parent) : QObject(parent) {
  m_secondTimer = new QTimer(this);
  m_secondTimer->setInterval(1000);
  connect(m_secondTimer, &QTimer::timeout, this, &SessionController::statsChanged);
}

SessionController::~SessionController() {
  if (m_preparation) {
    m_preparation->cancel();
    m_preparation->join();
  }
  if (m_host != nullptr) m_host->shutdown();
  if (m_client != nullptr) m_client->leave();
}

void SessionController::changeState(State next) {
  if (m_state == next) return;
  m_state = next;
  if (next == State::Live) {
    m_secondTimer->start();
  } else {
    m_secondTimer->stop();
  }
  emit stateChanged(next);
}

void SessionController::fail(const QString& message) {
  if (m_state == State::Failed || m_state == State::Left) return;
  m_errorText = message;
  m_dragging = false;
  changeState(State::Failed);
  if (m_host != nullptr) m_host->shutdown();
  if (m_client != nullptr) m_client->leave();
  emit lockChanged();
  emit failed(message);
}

// ---------------------------------------------------------------------------------------------------- ending

void SessionController::cancel() {
  if (m_state == State::Preparing) {
    if (m_preparation) m_preparation->cancel();
    // finishPreparation() reports the cancellation once the worker stops.
  } else if (m_state == State::Connecting) {
    fail(tr("Cancelled."));
  }
}

void SessionController::leave() {
  if (m_state != State::Preparing && m_state != State::Connecting && m_state != State::Live) return;
  m_leaving = true;
  m_dragging = false;
  if (m_preparation) m_preparation->cancel();
  if (m_host != nullptr) m_host->shutdown();
  if (m_client != nullptr) m_client->leave();
  changeState(State::Left);
  emit lockChanged();
  emit peersChanged();
}

quint16 SessionController::tcpPort() const {
  return m_host != nullptr && m_state == State::Live ? m_host->tcpPort() : 0;
}

session::PeerId SessionController::selfId() const {
  if (m_host != nullptr) return session::kHostPeer;
  if (m_client != nullptr) return m_client->peerId();
  return session::kNoPeer;
}

// ---------------------------------------------------------------------------------------------------- display

const spectral::ResolutionLevel* SessionController::level() const {
  if (m_host != nullptr) return m_fullLevel.get();
  return clientLevel();
}

const Eigen::MatrixXd& SessionController::displayRestPositions() const {
  if (m_host != nullptr && m_model) return m_model->V;
  if (clientLevel() != nullptr) return m_clientRestV;
  return kEmptyV;
}

const Eigen::MatrixXi& SessionController::displayFaces() const {
  if (m_host != nullptr && m_model) return m_model->F;
  if (const spectral::ResolutionLevel* l = clientLevel()) return l->F;
  return kEmptyF;
}

std::span<const float> SessionController::positions() const {
  if (m_host != nullptr) {
    if (m_hostPositionsStale && m_fullLevel) {
      m_reconstructionMs = timedReconstruction(*m_fullLevel, m_rest, m_lastZ, m_hostPositions);
      m_hostPositionsStale = false;
    }
    return m_hostPositions;
  }
  if (m_client != nullptr) return m_client->positions();
  return {};
}

Eigen::MatrixXd SessionController::coefficients() const {
  if (m_host != nullptr) return m_host->coefficients();
  if (m_client != nullptr && m_client->channel().hasFrame()) return m_client->channel().coefficients();
  return {};
}

double SessionController::reconstructionMs() const {
  if (m_client != nullptr) return m_client->reconstructionMs();
  return m_reconstructionMs;
}

Eigen::MatrixXf SessionController::positionsCoefficients() const {
  if (m_host != nullptr && m_fullLevel && m_lastZ.rows() == m_fullLevel->K.cols() && m_lastZ.cols() == 3) {
    return m_lastZ.cast<float>();
  }
  if (m_client != nullptr) return m_client->positionsCoefficients();
  return {};
}

double SessionController::timedReconstruction(const spectral::ResolutionLevel& level, std::span<const float> rest,
                                              const Eigen::MatrixXd& Z, std::vector<float>& out) {
  using Clock = std::chrono::steady_clock;
  const Eigen::MatrixXf Zf = Z.cast<float>();
  const auto start = Clock::now();
  out.resize(rest.size());
  spectral::reconstructInterleaved(level.K, rest, Zf, out);
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

// ---------------------------------------------------------------------------------------------------- levels

std::vector<LevelChoice> SessionController::levels() const {
  std::vector<LevelChoice> out;
  int n = 0;
  if (m_model) n = m_model->vertexCount();
  if (m_client != nullptr && m_client->session()) n = static_cast<int>(m_client->session()->vertexCount);
  if (n <= 0) return out;
  const QLocale locale;
  const std::uint32_t shown = m_client != nullptr ? m_client->levelVertexCount() : 0;
  out.push_back({0, tr("Full — %1 vertices").arg(locale.toString(n)),
                 m_host != nullptr || (shown != 0 ? shown == static_cast<std::uint32_t>(n) : m_levelTarget == 0)});
  if (m_host != nullptr) return out;
  if (m_client != nullptr && m_client->levels().complete()) {
    for (const session::LevelInfo& level : m_client->levels().levels) {
      if (level.levelId == 0) continue;  // the full model, listed above
      out.push_back(
          {level.vertexCount, tr("%1 vertices").arg(locale.toString(level.vertexCount)), shown == level.vertexCount});
    }
    return out;
  }
  for (int target : model::levelTargets(n)) {
    if (target >= n) continue;
    out.push_back({static_cast<std::uint32_t>(target), tr("≈ %1 vertices").arg(locale.toString(target)),
                   m_levelTarget == static_cast<std::uint32_t>(target)});
  }
  return out;
}

// ---------------------------------------------------------------------------------------------------- peers

session::PeerList SessionController::peers() const {
  if (m_host != nullptr && m_state == State::Live) return m_host->peerList();
  if (m_client != nullptr && m_state == State::Live) return m_client->peers();
  return {};
}

}  // namespace sc::app
