// ClientController, part 2: the resolution choices, the emulated network conditions, this client's own statistics
// and how its datagram channel stands.
#include "app/gui/client_controller.h"

#include "model/mesh_decimation.h"
#include "session/net/distortion_meter.h"
#include "session/net/session_client.h"

#include <QLocale>

#include <algorithm>
#include <chrono>
#include <cmath>

namespace sc::app {

std::vector<LevelChoice> ClientController::levels() const {
  if (m_client == nullptr || !m_client->session()) return {};
  const auto n = m_client->session()->vertexCount;
  if (n == 0) return {};
  const QLocale locale;
  const std::uint32_t shown = m_client->levelVertexCount();
  std::vector<LevelChoice> out;
  out.push_back({0, tr("Full — %1 vertices").arg(locale.toString(n)), shown != 0 ? shown == n : levelTarget() == 0});
  if (m_client->levels().complete()) {
    for (const session::LevelInfo& level : m_client->levels().levels) {
      if (level.levelId == 0) continue;  // the full model, listed above
      out.push_back(
          {level.vertexCount, tr("%1 vertices").arg(locale.toString(level.vertexCount)), shown == level.vertexCount});
    }
    return out;
  }
  for (int target : model::levelTargets(static_cast<int>(n))) {
    if (target < 0 || static_cast<std::uint32_t>(target) >= n) continue;
    out.push_back({static_cast<std::uint32_t>(target), tr("≈ %1 vertices").arg(locale.toString(target)),
                   levelTarget() == static_cast<std::uint32_t>(target)});
  }
  return out;
}

bool ClientController::levelPending() const { return m_client != nullptr && m_client->levelPending(); }

bool ClientController::setLevel(std::uint32_t target) {
  if (state() != State::Live || !m_client->requestResolution(target)) return false;
  setLevelTarget(target);
  endDrag();
  return true;
}

// ---------------------------------------------------------------------------------------------------- network

bool ClientController::setNetworkConditions(double loss, double burstLength, int delayMs, double rateMbit) {
  if (m_client == nullptr) return false;
  rateMbit = std::isfinite(rateMbit) ? std::max(0.0, rateMbit) : 0.0;
  loss = std::isfinite(loss) ? std::clamp(loss, 0.0, 1.0) : 0.0;
  burstLength = std::isfinite(burstLength) ? std::max(1.0, burstLength) : 1.0;
  delayMs = std::max(0, delayMs);
  std::optional<session::ImpairmentSettings> settings;
  if (loss > 0.0 || delayMs > 0 || rateMbit > 0.0) {
    settings.emplace();
    settings->loss = loss;
    settings->burst = burstLength > 1.0;
    settings->burstLength = burstLength;
    settings->delay = std::chrono::milliseconds(delayMs);
    settings->rate.bitsPerSecond = rateMbit * 1e6;
    // A fresh seed per change, so that returning to a setting does not replay the same losses.
    const std::optional<session::ImpairmentSettings>& previous = m_client->impairment();
    settings->seed = previous ? previous->seed + 1 : 1;
  }
  m_client->setImpairment(settings);
  emit networkConditionsChanged();
  return true;
}

NetworkConditions ClientController::networkConditions() const {
  NetworkConditions conditions;
  if (m_client == nullptr || !m_client->impairment()) return conditions;
  const session::ImpairmentSettings& s = *m_client->impairment();
  conditions.loss = s.loss;
  conditions.burstLength = s.burst ? s.burstLength : 1.0;
  conditions.delayMs = static_cast<int>(s.delay.count());
  conditions.rateMbit = s.rate.bitsPerSecond / 1e6;
  return conditions;
}

std::optional<session::ImpairmentSettings> ClientController::impairmentInEffect() const {
  const session::NetworkImpairment* impairment = m_client != nullptr ? m_client->channel().impairment() : nullptr;
  if (impairment == nullptr) return std::nullopt;
  return impairment->settings();
}

// ---------------------------------------------------------------------------------------------------- statistics

session::PeerList ClientController::peers() const {
  return state() == State::Live ? m_client->peers() : session::PeerList{};
}

std::optional<session::StatsReport> ClientController::stats(session::PeerId peer) const {
  if (state() != State::Live || peer != m_client->peerId() || !m_client->channel().isOpen()) return std::nullopt;
  return m_client->peekStats();  // what the next StatsReport carries (the distortion meter feeds setDistortion())
}

FrameReception ClientController::reception() const {
  if (m_client == nullptr) return {};
  const session::ClientDatagramChannel& channel = m_client->channel();
  const session::FramePredictor* predictor = channel.predictor();
  return {channel.hasFrame(), channel.receivedFrame(), channel.currentFrame(), predictor != nullptr,
          predictor != nullptr ? predictor->predictedFrames() : 0};
}

}  // namespace sc::app
