#include "session/engine/relay_audience.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace sc::session {
namespace {

Spread spreadOf(std::vector<double> values) {
  if (values.empty()) return {};
  std::sort(values.begin(), values.end());
  const auto rank = [&values](double fraction) {
    const auto index = static_cast<std::size_t>(std::ceil(fraction * static_cast<double>(values.size())));
    return values[std::clamp<std::size_t>(index, 1, values.size()) - 1];
  };
  return {values.front(), rank(0.5), rank(0.9), values.back()};
}

}  // namespace

bool RelayAudience::onStats(QByteArrayView message, Micros now) {
  const std::optional<RelayStats> stats = decodeRelayStats(message);
  if (!stats) {
    ++m_malformed;
    return false;
  }
  auto found = m_viewers.find(stats->viewer);
  if (found == m_viewers.end() && static_cast<int>(m_viewers.size()) >= kMaxTrackedViewers) {
    forgetSilent(now);
    if (static_cast<int>(m_viewers.size()) >= kMaxTrackedViewers) {  // still full: evict the stalest
      m_viewers.erase(std::min_element(m_viewers.begin(), m_viewers.end(),
                                       [](const auto& a, const auto& b) { return a.second.at < b.second.at; }));
    }
  }
  m_viewers[stats->viewer] = Entry{*stats, now};
  return true;
}

void RelayAudience::forgetSilent(Micros now) {
  std::erase_if(m_viewers, [now](const auto& item) { return now - item.second.at > kRelayViewerTimeout; });
}

RelayAudienceSummary RelayAudience::summary(Micros now) const {
  RelayAudienceSummary out;
  std::vector<double> loss, latency, distortionMean, distortionMax;
  for (const auto& item : m_viewers) {
    const Entry& entry = item.second;
    if (now - entry.at > kRelayViewerTimeout) continue;
    ++out.viewers;
    const double expected = static_cast<double>(entry.stats.applied) + static_cast<double>(entry.stats.lost);
    loss.push_back(expected > 0 ? static_cast<double>(entry.stats.lost) / expected : 0.0);
    latency.push_back(entry.stats.latencyP99Ms);
    out.badSignature += static_cast<std::int64_t>(std::min<std::uint64_t>(entry.stats.badSignature, 1u << 30));
    out.concealed += static_cast<std::int64_t>(std::min<std::uint64_t>(entry.stats.concealed, 1u << 30));
    if (entry.stats.distortions > 0) {
      distortionMean.push_back(entry.stats.distortionMeanPct);
      distortionMax.push_back(entry.stats.distortionMaxPct);
    }
  }
  out.lossFraction = spreadOf(std::move(loss));
  out.latencyP99Ms = spreadOf(std::move(latency));
  out.distortionViewers = static_cast<int>(distortionMean.size());
  out.distortionMeanPct = spreadOf(std::move(distortionMean));
  out.distortionMaxPct = spreadOf(std::move(distortionMax));
  out.malformed = m_malformed;
  return out;
}

}  // namespace sc::session
