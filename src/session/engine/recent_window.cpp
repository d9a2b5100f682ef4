#include "session/engine/recent_window.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <vector>

namespace sc::session {

// ---------------------------------------------------------------------------------------------------------------
// RecentSamples

RecentSamples::RecentSamples(Micros window, std::size_t capacity) : m_window(window), m_capacity(capacity) {
  assert(window.count() > 0 && capacity >= 1);
}

void RecentSamples::add(Micros at, Micros value) {
  m_samples.emplace_back(at, value);
  while (!m_samples.empty() && (m_samples.size() > m_capacity || m_samples.front().first <= at - m_window))
    m_samples.pop_front();
}

std::size_t RecentSamples::count(Micros now) const {
  return static_cast<std::size_t>(std::count_if(m_samples.begin(), m_samples.end(), [&](const auto& sample) {
    return sample.first > now - m_window && sample.first <= now;
  }));
}

double RecentSamples::percentileMs(Micros now, double fraction) const {
  std::vector<Micros> values;
  values.reserve(m_samples.size());
  for (const auto& [at, value] : m_samples)
    if (at > now - m_window && at <= now) values.push_back(value);
  if (values.empty()) return 0.0;
  const auto n = static_cast<double>(values.size());
  const auto rank = static_cast<std::size_t>(std::clamp(std::ceil(fraction * n), 1.0, n));  // nearest rank, 1-based
  const auto nth = values.begin() + static_cast<std::ptrdiff_t>(rank - 1);
  std::nth_element(values.begin(), nth, values.end());
  return static_cast<double>(nth->count()) / 1000.0;
}

// ---------------------------------------------------------------------------------------------------------------
// RecentLoss

RecentLoss::RecentLoss(Micros window, Micros step) : m_window(window), m_step(step) {
  assert(window.count() > 0 && step.count() > 0 && step < window);
}

void RecentLoss::record(Micros at, std::int64_t expected, std::int64_t received) {
  if (!m_snapshots.empty() && m_snapshots.back().at.count() / m_step.count() == at.count() / m_step.count()) {
    m_snapshots.back() = {at, expected, received};  // same step: the latest counts win
  } else {
    m_snapshots.push_back({at, expected, received});
  }
  // Keep one snapshot at or before the window's start (the baseline) and drop the ones before it.
  while (m_snapshots.size() > 2 && m_snapshots[1].at <= at - m_window) m_snapshots.pop_front();
}

double RecentLoss::fraction(Micros now, std::int64_t expected, std::int64_t received) const {
  // Baseline: the counts as the window opened, i.e. the latest snapshot at or before now − window; with none that
  // old, the window covers the whole stream so far (counts from zero).
  std::int64_t expectedBefore = 0;
  std::int64_t receivedBefore = 0;
  for (const Snapshot& s : m_snapshots) {
    if (s.at > now - m_window) break;
    expectedBefore = s.expected;
    receivedBefore = s.received;
  }
  const std::int64_t expectedIn = expected - expectedBefore;
  const std::int64_t lostIn = expectedIn - (received - receivedBefore);
  if (expectedIn <= 0 || lostIn <= 0) return 0.0;
  return std::min(1.0, static_cast<double>(lostIn) / static_cast<double>(expectedIn));
}

}  // namespace sc::session
