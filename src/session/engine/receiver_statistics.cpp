#include "session/engine/receiver_statistics.h"

#include <algorithm>
#include <cassert>
#include <cmath>

namespace sc::session {

namespace {

constexpr std::int64_t kSeqMod = 65536;

double toMs(Micros value) { return static_cast<double>(value.count()) / 1000.0; }

}  // namespace

// ---------------------------------------------------------------------------------------------------------------
// RateMeter

void RateMeter::add(Micros at, std::uint64_t amount) {
  m_entries.emplace_back(at, amount);
  while (!m_entries.empty() && m_entries.front().first <= at - m_window) m_entries.pop_front();
}

std::uint64_t RateMeter::sum(Micros now) const {
  std::uint64_t total = 0;
  for (const auto& [at, amount] : m_entries)
    if (at > now - m_window && at <= now) total += amount;
  return total;
}

double RateMeter::perSecond(Micros now) const {
  const double seconds = static_cast<double>(m_window.count()) / 1e6;
  return seconds > 0.0 ? static_cast<double>(sum(now)) / seconds : 0.0;
}

// ---------------------------------------------------------------------------------------------------------------
// ReceiverStatistics

ReceiverStatistics::ReceiverStatistics(Micros window, std::size_t latencyCapacity)
    : m_history(kHistory / 64, 0),
      m_payload(window),
      m_wire(window),
      m_frames(window),
      m_latencyCapacity(latencyCapacity) {
  assert(latencyCapacity >= 1 && "latencyCapacity must be >= 1");
  assert(window.count() > 0 && "the rate window must be positive");
  m_latency.reserve(std::min<std::size_t>(latencyCapacity, 8192));
}

bool ReceiverStatistics::seen(std::int64_t extended) const {
  const auto bit = static_cast<std::uint64_t>(extended % kHistory);
  return (m_history[bit / 64] >> (bit % 64)) & 1u;
}

void ReceiverStatistics::markSeen(std::int64_t extended) {
  const auto bit = static_cast<std::uint64_t>(extended % kHistory);
  m_history[bit / 64] |= std::uint64_t{1} << (bit % 64);
}

void ReceiverStatistics::restart(std::uint16_t sequence) {
  // RFC 3550 A.1 init_seq(): a new base; counts of expected/received start again.
  m_started = true;
  m_maxSeq = sequence;
  m_cycles = 0;
  m_base = sequence;
  m_badSeq = -1;
  m_received = 0;
  m_expectedPrior = 0;
  m_receivedPrior = 0;
  std::fill(m_history.begin(), m_history.end(), 0);
  m_recentLoss.restart();
}

ArrivalKind ReceiverStatistics::classify(std::uint16_t sequence, std::int64_t& extended) {
  const auto udelta = static_cast<std::uint16_t>(sequence - m_maxSeq);
  const std::int64_t highest = m_cycles + m_maxSeq;
  if (udelta == 0) {
    extended = highest;
    return ArrivalKind::Duplicate;
  }
  if (udelta < kMaxDropout) {  // ahead, perhaps after a gap; a smaller value means the counter wrapped
    if (sequence < m_maxSeq) m_cycles += kSeqMod;
    m_maxSeq = sequence;
    m_badSeq = -1;
    extended = m_cycles + m_maxSeq;
    const std::int64_t from = std::max(highest + 1, extended - kHistory + 1);
    for (std::int64_t n = from; n <= extended; ++n) {  // forget what used to occupy the slots entering the window
      const auto bit = static_cast<std::uint64_t>(n % kHistory);
      m_history[bit / 64] &= ~(std::uint64_t{1} << (bit % 64));
    }
    return ArrivalKind::InOrder;
  }
  if (udelta <= kSeqMod - kMaxMisorder) {  // implausible jump: accept only if the next one follows it
    if (m_badSeq == sequence) {
      restart(sequence);
      extended = m_base;
      return ArrivalKind::InOrder;
    }
    m_badSeq = (sequence + 1) % kSeqMod;
    return ArrivalKind::Jump;
  }
  extended = highest - (kSeqMod - udelta);     // behind by at most kMaxMisorder
  if (extended < 0) return ArrivalKind::Jump;  // before the very first cycle: cannot be placed
  if (extended < m_base) {
    m_base = extended;  // older than the first datagram seen: the stream started earlier than we thought
    return ArrivalKind::Late;
  }
  return seen(extended) ? ArrivalKind::Duplicate : ArrivalKind::Late;
}

ArrivalKind ReceiverStatistics::record(std::uint16_t sequence, Micros sentAt, Micros arrivedAt,
                                       std::size_t payloadBytes, std::size_t wireBytes) {
  m_payload.add(arrivedAt, payloadBytes);
  m_wire.add(arrivedAt, wireBytes);
  std::int64_t extended = 0;
  ArrivalKind kind = ArrivalKind::InOrder;
  if (!m_started) {
    restart(sequence);
    extended = m_base;
  } else {
    kind = classify(sequence, extended);
  }
  if (kind == ArrivalKind::Duplicate) ++m_duplicates;
  if (kind == ArrivalKind::Jump) ++m_jumps;
  if (kind == ArrivalKind::Duplicate || kind == ArrivalKind::Jump) return kind;
  if (kind == ArrivalKind::Late) ++m_late;
  markSeen(extended);
  ++m_received;
  m_recentLoss.record(arrivedAt, m_cycles + m_maxSeq - m_base + 1, m_received);

  const double transit = static_cast<double>((arrivedAt - sentAt).count());
  if (m_haveTransit) m_jitterUs += (std::abs(transit - m_lastTransitUs) - m_jitterUs) / 16.0;
  m_lastTransitUs = transit;
  m_haveTransit = true;
  recordLatency(arrivedAt - sentAt);
  m_recentLatency.add(arrivedAt, arrivedAt - sentAt);
  return kind;
}

void ReceiverStatistics::recordFrame(Micros at) { m_frames.add(at, 1); }

void ReceiverStatistics::clearLatency() {
  m_latency.clear();
  m_latencyNext = 0;
  m_latencyMax = Micros{0};
  m_recentLatency.clear();
}

void ReceiverStatistics::recordLatency(Micros latency) {
  m_latencyMax = std::max(m_latencyMax, latency);
  if (m_latency.size() < m_latencyCapacity) {
    m_latency.push_back(latency);
    return;
  }
  m_latency[m_latencyNext] = latency;
  m_latencyNext = (m_latencyNext + 1) % m_latencyCapacity;
}

double ReceiverStatistics::latencyPercentile(double fraction) const {
  if (m_latency.empty()) return 0.0;
  std::vector<Micros> samples = m_latency;
  const auto n = static_cast<double>(samples.size());
  const auto rank = static_cast<std::size_t>(std::max(1.0, std::ceil(fraction * n)));  // nearest rank, 1-based
  const auto nth = samples.begin() + static_cast<std::ptrdiff_t>(rank - 1);
  std::nth_element(samples.begin(), nth, samples.end());
  return toMs(*nth);
}

ReceiverReport ReceiverStatistics::peek(Micros now) const {
  ReceiverReport r;
  if (m_started) {
    const std::int64_t highest = m_cycles + m_maxSeq;
    r.extendedHighest = static_cast<std::uint32_t>(highest);
    r.expected = highest - m_base + 1;
  }
  r.received = m_received;
  r.cumulativeLost = std::max<std::int64_t>(0, r.expected - r.received);
  r.lossFraction = r.expected > 0 ? static_cast<double>(r.cumulativeLost) / static_cast<double>(r.expected) : 0.0;
  const std::int64_t expectedInterval = r.expected - m_expectedPrior;
  const std::int64_t lostInterval = expectedInterval - (m_received - m_receivedPrior);
  if (expectedInterval > 0 && lostInterval > 0) {
    r.intervalLossFraction = static_cast<double>(lostInterval) / static_cast<double>(expectedInterval);
    r.fractionLost = static_cast<std::uint8_t>(std::min<std::int64_t>(255, (lostInterval << 8) / expectedInterval));
  }
  r.jitterMs = m_jitterUs / 1000.0;
  r.late = m_late;
  r.duplicates = m_duplicates;
  r.jumps = m_jumps;
  r.payloadKbps = m_payload.kilobitsPerSecond(now);
  r.wireKbps = m_wire.kilobitsPerSecond(now);
  r.framesPerSecond = m_frames.perSecond(now);
  r.latencyP50Ms = latencyPercentile(0.50);
  r.latencyP99Ms = latencyPercentile(0.99);
  r.latencyMaxMs = toMs(m_latencyMax);
  r.recentLossFraction = m_recentLoss.fraction(now, r.expected, r.received);
  r.recentLatencyP50Ms = m_recentLatency.percentileMs(now, 0.50);
  r.recentLatencyP99Ms = m_recentLatency.percentileMs(now, 0.99);
  r.recentLatencySamples = m_recentLatency.count(now);
  return r;
}

ReceiverReport ReceiverStatistics::report(Micros now) {
  ReceiverReport r = peek(now);
  m_expectedPrior = r.expected;
  m_receivedPrior = m_received;
  return r;
}

}  // namespace sc::session
