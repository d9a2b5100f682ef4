#pragma once
// Figures over a recent time window (issue 16): the latency percentiles and the loss of the last few seconds, so
// that a stall long ago (the join, a paused process) leaves the figure once the window has passed it, and a loss
// burst now is not diluted by a long clean stretch before. Pure: the caller passes every timestamp (injected
// clock); no sockets, no timers. Not thread-safe.

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <deque>

namespace sc::session {

using Micros = std::chrono::microseconds;  ///< injected monotonic clock reading, origin arbitrary

/// The figures' window: the last 10 seconds.
inline constexpr Micros kRecentWindow{10'000'000};

/// Time-stamped samples in (now − window, now], at most `capacity` of them (the oldest go first), with percentiles
/// by nearest rank. Memory: O(capacity). Cost: add() amortised O(1); percentile() O(samples in the window).
class RecentSamples {
 public:
  explicit RecentSamples(Micros window = kRecentWindow, std::size_t capacity = 8192);

  /// Records `value` observed at `at`; `at` should not go backwards.
  void add(Micros at, Micros value);
  /// Nearest-rank percentile (fraction in (0, 1]) of the samples in (now − window, now], in ms; 0 when none.
  [[nodiscard]] double percentileMs(Micros now, double fraction) const;
  /// Samples in (now − window, now].
  [[nodiscard]] std::size_t count(Micros now) const;
  void clear() { m_samples.clear(); }

 private:
  Micros m_window;
  std::size_t m_capacity;
  std::deque<std::pair<Micros, Micros>> m_samples;  ///< (at, value), `at` ascending
};

/// Loss over (now − window, now] from the receiver's running counts (expected, received): the counts' growth since
/// the window opened. Snapshots are kept per `step` (the last one in a step wins), so memory is O(window / step)
/// and the window's start is exact to within one step. Cost: record() amortised O(1), fraction() O(window / step).
class RecentLoss {
 public:
  explicit RecentLoss(Micros window = kRecentWindow, Micros step = Micros{100'000});

  /// The running counts after something arrived at `at` (`at` should not go backwards; counts never decrease
  /// between two restart()s).
  void record(Micros at, std::int64_t expected, std::int64_t received);
  /// Lost / expected among the datagrams counted in (now − window, now], in [0, 1]; 0 when none were expected.
  /// `expected` and `received` are the running counts now.
  [[nodiscard]] double fraction(Micros now, std::int64_t expected, std::int64_t received) const;
  /// The counts start again from zero (sequence tracking restarted).
  void restart() { m_snapshots.clear(); }

 private:
  struct Snapshot {
    Micros at;
    std::int64_t expected;
    std::int64_t received;
  };
  Micros m_window;
  Micros m_step;
  std::deque<Snapshot> m_snapshots;  ///< `at` ascending; the front is the last one at or before the window start
};

}  // namespace sc::session
