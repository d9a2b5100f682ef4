#pragma once
// The session's one clock: std::chrono::steady_clock (CLOCK_MONOTONIC on Linux, shared by every process of one
// machine, so a host and a client on one machine can measure one-way latency from the datagram timestamp).

#include "session/engine/receiver_statistics.h"

#include <chrono>
#include <cstdint>

namespace sc::session {

/// Now, in microseconds of the monotonic clock.
inline Micros sessionNow() {
  return std::chrono::duration_cast<Micros>(std::chrono::steady_clock::now().time_since_epoch());
}

/// The datagram header's 32-bit timestamp of a clock reading (µs mod 2³²).
inline std::uint32_t wireTimestamp(Micros at) { return static_cast<std::uint32_t>(at.count()); }

/// The full clock reading a 32-bit timestamp stands for, taken as the latest reading ≤ `now` with those low bits
/// (valid while the true age is < 71 minutes). Cost: O(1).
inline Micros unwrapTimestamp(std::uint32_t timestamp, Micros now) {
  const std::uint32_t age = static_cast<std::uint32_t>(now.count()) - timestamp;  // mod 2³²
  return now - Micros{age};
}

}  // namespace sc::session
