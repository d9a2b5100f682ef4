#include "session/net/distortion_meter.h"

#include "session/net/distortion_worker.h"
#include "session/net/session_client.h"

#include "spectral/display_level.h"

#include <Eigen/Core>
#include <QtCore/QTimer>

#include <algorithm>
#include <cstdint>
#include <iterator>
#include <utility>
#include <vector>

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
  if (m_mode == Mode::Live) {
    m_worker = new DistortionWorker(this);
    connect(m_worker, &DistortionWorker::measured, this, &DistortionMeter::onMeasured);
  }
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
  const spectral::SharedDisplayLevel& level = m_client.displayLevel();
  if (!level || ready.empty()) return;
  if (m_worker->busy()) {
    m_skipped += static_cast<std::uint64_t>(ready.size());
    return;
  }
  const auto first = ready.size() > static_cast<std::size_t>(m_maxPerTick) ? ready.end() - m_maxPerTick : ready.begin();
  m_skipped += static_cast<std::uint64_t>(first - ready.begin());
  const auto m = static_cast<Eigen::Index>(level->basisSize());
  std::vector<DistortionPair> batch;
  for (auto it = first; it != ready.end(); ++it) {
    // Without any displayed frame at or before the reference (just joined, or a new level) there is nothing to
    // compare yet; the rest shape would make a meaningless distortion.
    if (!it->displayedAny) continue;
    if (it->shown.rows() != m || it->exact.rows() != m) continue;
    batch.push_back(std::move(*it));
  }
  m_worker->start(level, std::move(batch));
}

void DistortionMeter::onMeasured(const std::vector<double>& percents) {
  for (const double pct : percents) m_summary.add(pct);
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
