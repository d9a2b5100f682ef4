#pragma once
// Per-client receive statistics for the coefficient stream, with loss and jitter as RTCP receiver reports define
// them (RFC 3550 §6.4.1 and Appendix A.1/A.3/A.8; ../shared/design/protocol.md §4.2), plus kbit/s, frames per
// second and one-way latency. Pure: the caller passes every timestamp (injected clock); no sockets, no timers.
//
// Feed it each datagram that passed authentication (record()) and each frame the client applied (recordFrame()),
// and call report() about once a second for the receiver report. Time is in microseconds; Millis converts to it.
// Not thread-safe.

#include "session/engine/recent_window.h"

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <vector>

namespace sc::session {

/// Bytes (or events) in a sliding time window (now − window, now]. Also usable on the sending side ("out").
/// Memory and cost: O(entries in the window) per query; add() is amortised O(1).
class RateMeter {
 public:
  explicit RateMeter(Micros window = Micros{1'000'000}) : m_window(window) {}

  /// Records `amount` (bytes, or 1 per event) at time `at`; `at` should not go backwards.
  void add(Micros at, std::uint64_t amount);
  /// Sum of the amounts recorded in (now − window, now].
  std::uint64_t sum(Micros now) const;
  /// sum(now) per second of window.
  double perSecond(Micros now) const;
  /// 8·sum(now) / 1000 per second of window.
  double kilobitsPerSecond(Micros now) const { return perSecond(now) * 8.0 / 1000.0; }

 private:
  Micros m_window;
  std::deque<std::pair<Micros, std::uint64_t>> m_entries;
};

/// How record() classified a datagram.
enum class ArrivalKind {
  InOrder,    ///< newer than every datagram seen so far (possibly after a gap)
  Late,       ///< older than the newest seen but not seen before (filled a gap): counted as received
  Duplicate,  ///< already received: not counted as received
  Jump,       ///< implausible sequence jump (RFC 3550 A.1 "bad_seq"): ignored unless the next one follows it
};

/// One receiver report (cf. RTCP RR), produced by ReceiverStatistics::report().
struct ReceiverReport {
  std::uint32_t extendedHighest = 0;  ///< cycles·65536 + highest 16-bit sequence number
  std::int64_t expected = 0;          ///< extendedHighest − base + 1 (0 before any datagram)
  std::int64_t received = 0;          ///< distinct datagrams received
  std::int64_t cumulativeLost = 0;    ///< expected − received (≥ 0: duplicates are not counted as received)
  double lossFraction = 0.0;          ///< cumulativeLost / expected, in [0, 1]
  double intervalLossFraction = 0.0;  ///< lost/expected since the previous report, in [0, 1]
  std::uint8_t fractionLost = 0;      ///< RTCP 8-bit form of intervalLossFraction: (lost_interval << 8) / expected
  double jitterMs = 0.0;              ///< RFC 3550 interarrival jitter J
  std::uint64_t late = 0;             ///< datagrams that arrived after a newer one
  std::uint64_t duplicates = 0;
  std::uint64_t jumps = 0;
  double payloadKbps = 0.0;  ///< payload bytes over the last window (1 s), kbit/s
  double wireKbps = 0.0;     ///< wire bytes (payload + UDP/IP headers, as the caller counts them), kbit/s
  double framesPerSecond = 0.0;
  double latencyP50Ms = 0.0;  ///< one-way latency (arrival − send time), over the last latencyCapacity samples
  double latencyP99Ms = 0.0;
  double latencyMaxMs = 0.0;  ///< maximum over the whole run
  // The same figures over the last kRecentWindow (10 s) before the report's `now` (issue 16): what the docks show.
  double recentLossFraction = 0.0;  ///< lost/expected among the datagrams counted in the window, in [0, 1]
  double recentLatencyP50Ms = 0.0;  ///< percentiles of the samples that arrived in the window; 0 when none did
  double recentLatencyP99Ms = 0.0;
  std::size_t recentLatencySamples = 0;
};

/// Contract:
///  - Sequence numbers are 16-bit and extended as in RFC 3550 A.1: a number up to kMaxDropout ahead of the highest
///    is in order (a smaller value means the counter wrapped: cycles += 65536); up to kMaxMisorder behind is late or
///    duplicate (told apart by a bitmap of the last kHistory numbers); anything else is a Jump, ignored, unless the
///    next datagram carries the number after it, which restarts the statistics' sequence tracking from there.
///  - Departure from RFC 3550 A.3: duplicates are detected and not counted as received, so cumulativeLost is not
///    lowered by duplication (RFC: received counts every datagram, so it can go negative).
///  - Jitter (RFC 3550 A.8, in floating point): for each distinct datagram in arrival order,
///    D = (R_j − R_i) − (S_j − S_i) with S the sender's timestamp and R the arrival time, J += (|D| − J)/16.
///  - Latency = arrival − send time, meaningful when both use one clock (loopback); percentiles by nearest rank.
///  - The recent figures (recent*) cover (now − kRecentWindow, now] (RecentSamples, RecentLoss); the others the
///    whole run (loss since the statistics' last restart, latency over the last latencyCapacity samples).
/// Memory: O(kHistory bits + datagrams and frames in the rate window + latencyCapacity + recent samples).
/// Cost: O(1) amortised per record(); report() O(window entries + latencyCapacity).
class ReceiverStatistics {
 public:
  static constexpr int kMaxDropout = 3000;
  static constexpr int kMaxMisorder = 100;
  static constexpr int kHistory = 1024;  ///< > kMaxMisorder

  /// @param[in] window  rate window for kbit/s and fps. @param[in] latencyCapacity  latency samples kept (≥ 1).
  explicit ReceiverStatistics(Micros window = Micros{1'000'000}, std::size_t latencyCapacity = 8192);

  /// One authenticated datagram. @param sentAt the sender's timestamp from the datagram; @param arrivedAt local
  /// arrival time; @param payloadBytes UDP payload; @param wireBytes what the caller counts on the wire.
  ArrivalKind record(std::uint16_t sequence, Micros sentAt, Micros arrivedAt, std::size_t payloadBytes,
                     std::size_t wireBytes);

  /// One frame applied (displayed) at `at`.
  void recordFrame(Micros at);

  /// Current figures; starts a new interval for intervalLossFraction / fractionLost.
  ReceiverReport report(Micros now);
  /// The same figures without starting a new interval (interval fields: since the last report()).
  ReceiverReport peek(Micros now) const;
  /// Forgets the latency samples (percentiles, recent ones included, and maximum start over), e.g. to measure one
  /// phase of a run.
  void clearLatency();

 private:
  ArrivalKind classify(std::uint16_t sequence, std::int64_t& extended);
  void restart(std::uint16_t sequence);
  bool seen(std::int64_t extended) const;
  void markSeen(std::int64_t extended);
  void recordLatency(Micros latency);
  double latencyPercentile(double fraction) const;

  bool m_started = false;
  std::uint16_t m_maxSeq = 0;
  std::int64_t m_cycles = 0;
  std::int64_t m_base = 0;  ///< extended number of the first datagram
  std::int64_t m_badSeq = -1;
  std::vector<std::uint64_t> m_history;  ///< bit (extended mod kHistory) set: that number was received
  std::int64_t m_received = 0;
  std::int64_t m_expectedPrior = 0;
  std::int64_t m_receivedPrior = 0;
  std::uint64_t m_late = 0;
  std::uint64_t m_duplicates = 0;
  std::uint64_t m_jumps = 0;

  bool m_haveTransit = false;
  double m_lastTransitUs = 0.0;
  double m_jitterUs = 0.0;

  RateMeter m_payload;
  RateMeter m_wire;
  RateMeter m_frames;

  std::vector<Micros> m_latency;  ///< ring buffer of the last latencyCapacity samples
  std::size_t m_latencyNext = 0;
  std::size_t m_latencyCapacity;
  Micros m_latencyMax{0};

  RecentSamples m_recentLatency;
  RecentLoss m_recentLoss;
};

}  // namespace sc::session
