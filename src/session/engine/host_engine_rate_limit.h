#pragma once
// A token bucket on the session clock, for the host's per-peer rate limits (docs/security.md, "Hostile member"):
// `burst` tokens at first, refilled at `perSecond`, one taken per event. take() says whether the event is within
// the rate. Cost: O(1), no allocation. perSecond ≤ 0 means no limit.

#include "session/engine/receiver_statistics.h"

#include <algorithm>
#include <chrono>
#include <optional>

namespace sc::session {

/// A rate: `perSecond` sustained, `burst` at once.
struct RateLimit {
  double perSecond = 0.0;  ///< ≤ 0: unlimited
  double burst = 1.0;      ///< ≥ 1
};

class TokenBucket {
 public:
  TokenBucket() = default;
  explicit TokenBucket(RateLimit limit) : m_limit(limit), m_tokens(std::max(limit.burst, 1.0)) {}

  /// True (and one token taken) when an event at `now` is within the rate.
  bool take(Micros now) {
    if (m_limit.perSecond <= 0.0) return true;
    if (m_last) {
      const double seconds = std::chrono::duration<double>(now - *m_last).count();
      m_tokens = std::min(std::max(m_limit.burst, 1.0), m_tokens + std::max(seconds, 0.0) * m_limit.perSecond);
    }
    m_last = now;
    if (m_tokens < 1.0) return false;
    m_tokens -= 1.0;
    return true;
  }

 private:
  RateLimit m_limit;
  double m_tokens = 1.0;
  std::optional<Micros> m_last;
};

}  // namespace sc::session
