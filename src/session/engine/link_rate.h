#pragma once
// The bottleneck of an emulated access link (issue 17 item 1): a token bucket (rate in bit/s, burst in bytes) in
// front of a bounded FIFO queue, shared by everything a client receives: its datagrams (admit(): a flooded link
// first delays them, then drops at the tail once the queue is full) and its TLS stream (available()/consume():
// the reader takes only what the bucket allows and waits otherwise; TCP's flow control then backs up to the
// sender, nothing is dropped). Pure: sizes and an injected clock in, times out; no sockets, no timers.
//
// Model (a virtual-time form of the token bucket, GCRA): E is the instant at which the bucket would be full again
// (tokens(t) = B − r·(E − t)/8 bytes for t < E, B from E on); cost(s) = 8·s/r seconds, tau = cost(B).
//   datagram of s bytes arriving at t:  E' = max(E, t) + cost(s),  departure d = max(t, E' − tau);
//                                       tail drop when d − t > cost(Q) (more than Q bytes queued ahead), E kept;
//   stream: available(t) = clamp(B − r·(E − t)/8, 0, B) bytes;  consume(s, t): E = max(E, t) + cost(s).
// Departures are in arrival order (FIFO) and never earlier than the arrival. Over any long busy interval the
// bytes through are r·T/8 + B at most. A datagram larger than B simply waits until the bucket has paid it off.
// Times are kept in double microseconds (exact for rates whose cost per byte is a whole number of µs, e.g.
// 8 Mbit/s = 1 µs per byte); returned times are rounded up to whole microseconds. Deterministic: no randomness.
// Not thread-safe; one per client link (shared by the datagram and stream paths of one thread).

#include "session/engine/recent_window.h"

#include <cstddef>
#include <cstdint>
#include <optional>

namespace sc::session {

struct LinkRateSettings {
  /// Link rate in bit/s; ≤ 0 (or not finite) means no rate limit (no LinkRate is made, see NetworkImpairment).
  /// A LinkRate clamps it to [kMinBitsPerSecond, kMaxBitsPerSecond].
  double bitsPerSecond = 0.0;
  /// Bucket depth B in bytes; 0: automatic, max(32 KiB, 4 ms at the rate) (a stream reader woken by a 1 ms timer
  /// keeps the rate). At least kMinBurstBytes.
  std::uint32_t burstBytes = 0;
  /// Queue bound Q in bytes (datagrams waiting for tokens); 0: automatic, max(64 KiB, 200 ms at the rate).
  std::uint32_t queueBytes = 0;
  /// Charged per datagram on top of its payload (UDP 8 + IPv4 20 bytes). The stream is charged the bytes the
  /// application reads (TLS and TCP/IP headers, about 3%, are not charged).
  std::uint32_t datagramOverheadBytes = 28;
};

class LinkRate {
 public:
  static constexpr double kMinBitsPerSecond = 1000.0;
  static constexpr double kMaxBitsPerSecond = 100e9;
  static constexpr std::uint32_t kMinBurstBytes = 1500;

  explicit LinkRate(const LinkRateSettings& settings);

  /// One datagram of `bytes` (payload; the overhead is added here) arriving at `now`: its departure time from the
  /// bottleneck (≥ now), or nullopt when the queue is full (tail drop, counted in dropped()). Cost: O(1).
  std::optional<Micros> admit(std::size_t bytes, Micros now);

  /// Bytes the stream may read at `now` without waiting, 0..burstBytes(). Cost: O(1).
  std::size_t available(Micros now) const;
  /// The stream read `bytes` at `now` (normally ≤ available(now); more makes later readers wait). Cost: O(1).
  void consume(std::size_t bytes, Micros now);
  /// Earliest instant ≥ now at which available() ≥ min(bytes, burstBytes()). Cost: O(1).
  Micros availableAt(std::size_t bytes, Micros now) const;

  /// Bytes queued ahead of a datagram arriving at `now` (beyond the burst), 0 when the bucket has tokens.
  std::size_t backlog(Micros now) const;

  double bitsPerSecond() const { return m_settings.bitsPerSecond; }
  std::uint32_t burstBytes() const { return m_settings.burstBytes; }
  std::uint32_t queueBytes() const { return m_settings.queueBytes; }
  const LinkRateSettings& settings() const { return m_settings; }

  std::uint64_t datagramsAdmitted() const { return m_admitted; }
  std::uint64_t dropped() const { return m_dropped; }              ///< datagrams tail-dropped
  std::uint64_t streamBytes() const { return m_streamBytes; }      ///< consumed by the stream
  std::uint64_t datagramBytes() const { return m_datagramBytes; }  ///< admitted, overhead included

 private:
  double cost(double bytes) const { return bytes * m_microsPerByte; }  ///< µs
  double full(Micros now) const;                                       ///< max(E, now) as double µs

  LinkRateSettings m_settings;
  double m_microsPerByte = 0.0;
  double m_tau = 0.0;            ///< cost(B), µs
  double m_queueDelay = 0.0;     ///< cost(Q), µs
  std::optional<double> m_full;  ///< E, µs; nullopt: full since ever
  std::uint64_t m_admitted = 0;
  std::uint64_t m_dropped = 0;
  std::uint64_t m_streamBytes = 0;
  std::uint64_t m_datagramBytes = 0;
};

}  // namespace sc::session
