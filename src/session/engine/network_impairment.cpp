#include "session/engine/network_impairment.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <utility>

namespace sc::session {

namespace {

double clamp01(double value) { return std::isfinite(value) ? std::clamp(value, 0.0, 1.0) : 0.0; }
Millis nonNegative(Millis value) { return std::max(value, Millis{0}); }

}  // namespace

NetworkImpairment::NetworkImpairment(const ImpairmentSettings& settings, std::shared_ptr<LinkRate> link)
    : m_settings(settings), m_rng(settings.seed), m_link(std::move(link)) {
  if (!m_link && m_settings.rate.bitsPerSecond > 0.0) m_link = std::make_shared<LinkRate>(m_settings.rate);
  if (m_link) m_settings.rate = m_link->settings();
  m_settings.loss = clamp01(m_settings.loss);
  m_settings.reorder = clamp01(m_settings.reorder);
  m_settings.duplicate = clamp01(m_settings.duplicate);
  m_settings.burstLength = std::isfinite(m_settings.burstLength) ? std::max(m_settings.burstLength, 1.0) : 1.0;
  m_settings.delay = nonNegative(m_settings.delay);
  m_settings.jitter = nonNegative(m_settings.jitter);
  m_settings.reorderGap = nonNegative(m_settings.reorderGap);
  const double loss = m_settings.loss;
  if (!m_settings.burst) {
    m_goodToBad = loss;
    m_badToGood = 1.0 - loss;
  } else if (loss >= 1.0) {
    m_goodToBad = 1.0;
    m_badToGood = 0.0;
  } else {
    m_badToGood = 1.0 / m_settings.burstLength;
    m_goodToBad = std::min(1.0, m_badToGood * loss / (1.0 - loss));
  }
}

double NetworkImpairment::uniform01() {
  return static_cast<double>(m_rng() >> 11) * 0x1.0p-53;  // 53 bits: exact, portable across standard libraries
}

bool NetworkImpairment::bernoulli(double probability) {
  if (probability <= 0.0) return false;
  if (probability >= 1.0) return true;
  return uniform01() < probability;
}

bool NetworkImpairment::lose() {
  if (!m_settings.burst) return bernoulli(m_settings.loss);
  // Pure Gilbert: transition first, then the state decides (Bad = lost). Stationary P(Bad) = p/(p + r).
  m_bad = m_bad ? !bernoulli(m_badToGood) : bernoulli(m_goodToBad);
  return m_bad;
}

Millis NetworkImpairment::jitterSample() {
  const double spread = static_cast<double>(m_settings.jitter.count());
  if (spread <= 0.0) return Millis{0};
  double sample = 0.0;
  if (m_settings.jitterShape == JitterShape::Uniform) {
    sample = (2.0 * uniform01() - 1.0) * spread;
  } else {
    // Box–Muller with u1 in (0, 1]; truncated to ±3σ.
    const double u1 = 1.0 - uniform01();
    const double u2 = uniform01();
    const double normal = std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * std::numbers::pi * u2);
    sample = std::clamp(normal, -3.0, 3.0) * spread;
  }
  return Millis{std::llround(sample)};
}

void NetworkImpairment::push(QByteArrayView bytes, Millis now) {
  ++m_offered;
  if (lose()) {
    ++m_dropped;
    return;
  }
  Millis departure = now;
  if (m_link) {
    const std::optional<Micros> leaves = m_link->admit(static_cast<std::size_t>(bytes.size()), now);
    if (!leaves) {
      ++m_dropped;
      ++m_rateDropped;
      return;
    }
    departure = std::chrono::ceil<Millis>(*leaves);
  }
  const Millis base = departure + m_settings.delay;
  Millis due = std::max(departure, base + jitterSample());
  if (bernoulli(m_settings.reorder)) {
    ++m_reordered;
    due += m_settings.reorderGap;
  }
  const bool twice = bernoulli(m_settings.duplicate);
  const QByteArray copy = bytes.toByteArray();
  m_queue.push({due, m_order++, copy});
  if (twice) {
    ++m_duplicated;
    m_queue.push({std::max(departure, base + jitterSample()), m_order++, copy});
  }
}

std::vector<QByteArray> NetworkImpairment::popDue(Millis now) {
  std::vector<QByteArray> out;
  while (!m_queue.empty() && m_queue.top().due <= now) {
    out.push_back(m_queue.top().bytes);
    m_queue.pop();
  }
  m_delivered += out.size();
  return out;
}

Millis NetworkImpairment::nextDue() const { return m_queue.empty() ? Millis::max() : m_queue.top().due; }

}  // namespace sc::session
