// SessionController, client side: joining (SessionClient and its distortion meter), the client's levels, its
// emulated network conditions, its own statistics, the once-a-second reconstruction timing, and how the host's
// certificate was trusted (pinned fingerprint or trust on first use, session::KnownHosts).
#include "app/gui/session_controller.h"

#include "session/net/distortion_meter.h"
#include "session/net/session_client.h"
#include "session/engine/session_clock.h"
#include "session/net/session_host.h"
#include "session/net/tls_known_hosts.h"
#include "spectral/resolution_level.h"

#include <QTimer>

#include <algorithm>
#include <chrono>
#include <cmath>

namespace sc::app {

bool SessionController::join(const JoinSettings& settings) {
  if (m_state != State::Idle) return false;
  m_role = Role::Client;
  m_levelTarget = settings.level;
  session::SessionClientOptions options;
  options.host = settings.host;
  options.port = settings.port;
  options.name = settings.name;
  options.password = settings.password;
  options.level = settings.level;
  options.levelFraction = settings.levelFraction;
  options.impairment = settings.impairment;
  options.fingerprint = settings.fingerprint;
  options.trustOnFirstUse = true;  // as shapecast-cli join: remember the first fingerprint, refuse a change
  options.knownHostsFile = settings.knownHostsFile;
  m_joinFraction = settings.levelFraction;
  if (!settings.fingerprint.isEmpty()) {
    m_joinTrust = HostTrust::Pinned;
  } else {
    const bool known = session::KnownHosts(settings.knownHostsFile).lookup(settings.host, settings.port).has_value();
    m_joinTrust = known ? HostTrust::Known : HostTrust::FirstUse;
  }
  m_client = new session::SessionClient(options, this);
  m_meter = new session::DistortionMeter(*m_client, session::DistortionMeter::Mode::Live, m_client);
  connect(m_client, &session::SessionClient::stateChanged, this, &SessionController::onClientState);
  connect(m_client, &session::SessionClient::levelReady, this, &SessionController::onClientLevel);
  connect(m_client, &session::SessionClient::levelFailed, this,
          [this](const QString& reason) { emit failed(tr("The new resolution could not be loaded: %1").arg(reason)); });
  connect(m_client, &session::SessionClient::modelProgress, this, [this](quint64 received, quint64 total) {
    const int percent = total == 0 ? 0 : static_cast<int>(100 * received / total);
    emit progress(percent, tr("Downloading the model"));
  });
  connect(m_client, &session::SessionClient::positionsUpdated, this, &SessionController::positionsChanged);
  connect(m_client, &session::SessionClient::lockChanged, this, &SessionController::onLockChanged);
  connect(m_client, &session::SessionClient::peersChanged, this, &SessionController::peersChanged);
  connect(m_client, &session::SessionClient::levelsChanged, this, &SessionController::levelsChanged);
  changeState(State::Connecting);
  emit progress(0, tr("Connecting to %1:%2").arg(settings.host).arg(settings.port));
  m_client->start();
  return true;
}

void SessionController::onClientState() {
  using S = session::SessionClient::State;
  const S s = m_client->state();
  if (s == S::Failed) {
    if (m_state == State::Live) {
      fail(tr("The session ended: %1").arg(m_client->errorText()));
    } else {
      fail(tr("Could not join the session: %1").arg(m_client->errorText()));
    }
  } else if (s == S::Left) {
    if (!m_leaving) {
      fail(tr("The host ended the session."));
    }
  }
}

void SessionController::onClientLevel() {
  m_clientRestV = m_client->level() != nullptr ? m_client->level()->restV : Eigen::MatrixXd();
  m_constraintsSent = false;  // ids of the previous level mean nothing on the new one
  m_handle.clear();
  m_anchors.clear();
  if (m_state == State::Connecting) {
    if (m_joinFraction && *m_joinFraction > 0.0 && *m_joinFraction < 1.0 && m_client->session()) {
      m_levelTarget = static_cast<std::uint32_t>(std::round(*m_joinFraction * m_client->session()->vertexCount));
    }
    emit progress(100, tr("Joined"));
    changeState(State::Live);
  }
  emit statsChanged();
  emit meshChanged();
  emit positionsChanged();
  emit peersChanged();
  emit lockChanged();
}

HostTrust SessionController::hostTrust() const {
  // The handshake starts only once the certificate passed the fingerprint check (SessionClient::onEncrypted).
  if (m_client == nullptr || m_client->handshake().state() == session::ClientHandshake::State::SendHello) {
    return HostTrust::None;
  }
  return m_joinTrust;
}

bool SessionController::fingerprintRefused() const {
  // A certificate was seen but the handshake never started: the fingerprint check is the only thing in between.
  return m_client != nullptr && m_client->state() == session::SessionClient::State::Failed &&
         !m_client->hostFingerprint().isEmpty() &&
         m_client->handshake().state() == session::ClientHandshake::State::SendHello;
}

const spectral::ResolutionLevel* SessionController::clientLevel() const {
  return m_client != nullptr ? m_client->level() : nullptr;
}

bool SessionController::setLevel(std::uint32_t target) {
  if (m_client == nullptr || m_state != State::Live) return false;
  if (!m_client->requestResolution(target)) return false;
  m_levelTarget = target;
  m_dragging = false;
  return true;
}

// ---------------------------------------------------------------------------------------------------- network

bool SessionController::setNetworkConditions(double loss, double burstLength, int delayMs) {
  if (m_client == nullptr) return false;
  loss = std::isfinite(loss) ? std::clamp(loss, 0.0, 1.0) : 0.0;
  burstLength = std::isfinite(burstLength) ? std::max(1.0, burstLength) : 1.0;
  delayMs = std::max(0, delayMs);
  std::optional<session::ImpairmentSettings> settings;
  if (loss > 0.0 || delayMs > 0) {
    settings.emplace();
    settings->loss = loss;
    settings->burst = burstLength > 1.0;
    settings->burstLength = burstLength;
    settings->delay = std::chrono::milliseconds(delayMs);
    // A fresh seed per change, so that returning to a setting does not replay the same losses.
    const std::optional<session::ImpairmentSettings>& previous = m_client->impairment();
    settings->seed = previous ? previous->seed + 1 : 1;
  }
  m_client->setImpairment(settings);
  emit networkConditionsChanged();
  return true;
}

NetworkConditions SessionController::networkConditions() const {
  NetworkConditions conditions;
  if (m_client == nullptr || !m_client->impairment()) return conditions;
  const session::ImpairmentSettings& s = *m_client->impairment();
  conditions.loss = s.loss;
  conditions.burstLength = s.burst ? s.burstLength : 1.0;
  conditions.delayMs = static_cast<int>(s.delay.count());
  return conditions;
}

// ---------------------------------------------------------------------------------------------------- statistics

std::optional<session::StatsReport> SessionController::stats(session::PeerId peer) const {
  if (m_state != State::Live) return std::nullopt;
  if (m_host != nullptr) return m_host->stats(peer);
  if (m_client == nullptr || peer != m_client->peerId() || !m_client->channel().isOpen()) return std::nullopt;
  const auto figure = [](double v) { return std::isfinite(v) && v > 0.0 ? v : 0.0; };
  const session::ReceiverReport r = m_client->channel().peek(session::sessionNow());
  session::StatsReport s;
  s.vertexCount = m_client->levelVertexCount();
  s.framesApplied = static_cast<std::uint32_t>(m_client->channel().framesApplied());
  s.received = static_cast<std::uint64_t>(std::max<std::int64_t>(0, r.received));
  s.lost = static_cast<std::uint64_t>(std::max<std::int64_t>(0, r.cumulativeLost));
  s.late = r.late;
  s.dropped = m_client->channel().droppedDatagrams();
  s.lossFraction = figure(r.lossFraction);
  s.jitterMs = figure(r.jitterMs);
  s.payloadKbpsIn = figure(r.payloadKbps);
  s.wireKbpsIn = figure(r.wireKbps);
  s.framesPerSecond = figure(r.framesPerSecond);
  s.latencyP50Ms = figure(r.latencyP50Ms);
  s.latencyP99Ms = figure(r.latencyP99Ms);
  if (m_meter != nullptr) {
    s.hdMaxPct = figure(m_meter->summary().maxPct);
    s.hdMeanPct = figure(m_meter->summary().meanPct);
    s.hdLastPct = figure(m_meter->summary().lastPct);
  }
  return s;
}

}  // namespace sc::app
