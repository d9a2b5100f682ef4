#include "session/net/distortion_meter.h"

#include "session/net/session_client.h"
#include "spectral/hausdorff.h"

#include <QtCore/QTimer>

#include <algorithm>
#include <iterator>

namespace sc::session {

DistortionMeter::DistortionMeter(SessionClient& client, Mode mode, QObject* parent, std::chrono::milliseconds period,
                                 int maxPerTick)
    : QObject(parent), m_client(client), m_mode(mode), m_maxPerTick(std::max(1, maxPerTick)) {
  ClientDatagramChannel& channel = client.channel();
  connect(&channel, &ClientDatagramChannel::frameUpdated, this,
          [this, &channel](std::uint32_t frame) { m_probe.displayed(frame, channel.coefficients()); });
  connect(&channel, &ClientDatagramChannel::predictionWithdrawn, this,
          [this](std::uint32_t frame) { m_probe.withdraw(frame); });
  connect(&client, &SessionClient::keyframeReceived, this,
          [this](std::uint32_t frame, const Eigen::MatrixXd& Z) { m_probe.reference(frame, Z); });
  connect(&client, &SessionClient::levelReady, this, [this, &channel] {
    m_probe.reset();
    m_recorded.clear();
    // The new level shows the current Z at once: that is what is displayed from now on.
    if (channel.hasFrame()) m_probe.displayed(channel.currentFrame(), channel.coefficients());
  });
  m_timer = new QTimer(this);
  connect(m_timer, &QTimer::timeout, this, &DistortionMeter::tick);
  m_timer->start(period);
}

void DistortionMeter::tick() {
  std::vector<DistortionPair> ready = m_probe.takeReady(m_client.channel().currentFrame());
  if (m_mode == Mode::Record) {
    std::move(ready.begin(), ready.end(), std::back_inserter(m_recorded));
    return;
  }
  const spectral::ResolutionLevel* level = m_client.level();
  if (level == nullptr || ready.empty()) return;
  const auto first = ready.size() > static_cast<std::size_t>(m_maxPerTick) ? ready.end() - m_maxPerTick : ready.begin();
  m_skipped += static_cast<std::uint64_t>(first - ready.begin());
  const double diagonal = spectral::boundingBoxDiagonal(level->restV);
  for (auto it = first; it != ready.end(); ++it) {
    // Without any displayed frame at or before the reference (just joined, or a new level) there is nothing to
    // compare yet; the rest shape would make a meaningless distortion.
    if (!it->displayedAny) continue;
    if (it->shown.rows() != level->K.cols() || it->exact.rows() != level->K.cols()) continue;
    m_summary.add(distortionPercent(*level, it->shown, it->exact, diagonal));
  }
  m_client.setDistortion(m_summary.maxPct, m_summary.meanPct, m_summary.lastPct);
}

std::vector<DistortionPair> DistortionMeter::takeRecorded() {
  std::vector<DistortionPair> all = std::move(m_recorded);
  m_recorded.clear();
  std::vector<DistortionPair> pending = m_probe.takeAll();
  std::move(pending.begin(), pending.end(), std::back_inserter(all));
  return all;
}

void DistortionMeter::clearRecorded() {
  m_recorded.clear();
  m_probe.takeReady(m_client.channel().currentFrame());
}

}  // namespace sc::session
