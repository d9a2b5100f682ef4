// ClientEngine: what tick() runs and when (nextWakeUp()): the coalesced frame publication, the per-second host
// silence check, Heartbeat and StatsReport, and the lock renewals.

#include "session/engine/client_engine.h"

#include <algorithm>
#include <cmath>

namespace sc::session {
namespace {

/// StatsReport doubles must be finite and ≥ 0.
double figure(double value) { return std::isfinite(value) && value > 0.0 ? value : 0.0; }

}  // namespace

ClientActions ClientEngine::tick(Micros now, const ReceiverSampler& sample) {
  ClientActions out;
  if (m_frameDirty) publishFrame(out);
  if (live() && now >= m_nextSecond) {
    m_nextSecond += kSecond;
    if (m_nextSecond <= now) m_nextSecond = now + kSecond;  // after a stall: no burst of catch-up beats
    everySecond(now, sample, out);
  }
  if (live() && m_lock) sendLock(m_lock->pollRenew(std::chrono::duration_cast<Millis>(now)), out);
  return out;
}

std::optional<Micros> ClientEngine::nextWakeUp() const {
  std::optional<Micros> due;
  const auto earliest = [&due](Micros at) { due = due ? std::min(*due, at) : at; };
  if (m_frameDirty) earliest(m_dirtySince);
  if (live()) {
    earliest(m_nextSecond);
    if (const std::optional<Millis> renew = m_lock ? m_lock->nextRenewDue() : std::nullopt) earliest(*renew);
  }
  return due;
}

void ClientEngine::everySecond(Micros now, const ReceiverSampler& sample, ClientActions& out) {
  if (now - m_lastHeard > std::chrono::duration_cast<Micros>(m_config.hostTimeout)) {
    fail(QStringLiteral("host lost: not responding for %1 s").arg(m_config.hostTimeout.count() / 1000.0), out);
    return;
  }
  send(Heartbeat{m_heartbeatSequence++}, out);
  send(statsReport(sample ? sample(now) : ReceiverSample{}), out);
}

StatsReport ClientEngine::statsReport(const ReceiverSample& sample) const {
  const ReceiverReport& r = sample.report;
  StatsReport stats;
  stats.vertexCount = levelVertexCount();
  stats.framesApplied = static_cast<std::uint32_t>(sample.framesApplied);
  stats.received = static_cast<std::uint64_t>(std::max<std::int64_t>(0, r.received));
  stats.lost = static_cast<std::uint64_t>(std::max<std::int64_t>(0, r.cumulativeLost));
  stats.late = r.late;
  stats.dropped = sample.dropped + m_framesRefused;
  // The fractions and percentiles cover the last kRecentWindow (10 s, issue 16); `received` and `lost` stay
  // cumulative, so the loss since the join is still lost / (received + lost).
  stats.lossFraction = figure(r.recentLossFraction);
  stats.jitterMs = figure(r.jitterMs);
  stats.payloadKbpsIn = figure(r.payloadKbps);
  stats.wireKbpsIn = figure(r.wireKbps);
  stats.framesPerSecond = figure(r.framesPerSecond);
  stats.latencyP50Ms = figure(r.recentLatencyP50Ms);
  stats.latencyP99Ms = figure(r.recentLatencyP99Ms);
  stats.hdMaxPct = figure(m_hdMax);
  stats.hdMeanPct = figure(m_hdMean);
  stats.hdLastPct = figure(m_hdLast);
  return stats;
}

}  // namespace sc::session
