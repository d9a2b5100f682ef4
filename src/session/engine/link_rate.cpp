#include "session/engine/link_rate.h"

#include <algorithm>
#include <cmath>

namespace sc::session {
namespace {

double micros(Micros at) { return static_cast<double>(at.count()); }
Micros ceilMicros(double at) { return Micros{static_cast<Micros::rep>(std::ceil(at))}; }

/// Bytes sent in `seconds` at `bitsPerSecond`, as a 32-bit count (saturated).
std::uint32_t bytesIn(double seconds, double bitsPerSecond) {
  return static_cast<std::uint32_t>(std::min(seconds * bitsPerSecond / 8.0, 4.0e9));
}

}  // namespace

LinkRate::LinkRate(const LinkRateSettings& settings) : m_settings(settings) {
  double& rate = m_settings.bitsPerSecond;
  rate = std::isfinite(rate) ? std::clamp(rate, kMinBitsPerSecond, kMaxBitsPerSecond) : kMinBitsPerSecond;
  if (m_settings.burstBytes == 0) m_settings.burstBytes = std::max<std::uint32_t>(32 * 1024, bytesIn(0.004, rate));
  m_settings.burstBytes = std::max(m_settings.burstBytes, kMinBurstBytes);
  if (m_settings.queueBytes == 0) m_settings.queueBytes = std::max<std::uint32_t>(64 * 1024, bytesIn(0.2, rate));
  m_microsPerByte = 8.0e6 / rate;
  m_tau = cost(m_settings.burstBytes);
  m_queueDelay = cost(m_settings.queueBytes);
}

double LinkRate::full(Micros now) const { return m_full ? std::max(*m_full, micros(now)) : micros(now); }

std::optional<Micros> LinkRate::admit(std::size_t bytes, Micros now) {
  const double t = micros(now);
  const double charged = static_cast<double>(bytes) + m_settings.datagramOverheadBytes;
  const double next = full(now) + cost(charged);
  const double departure = std::max(t, next - m_tau);
  if (departure - t > m_queueDelay) {
    ++m_dropped;
    return std::nullopt;
  }
  m_full = next;
  ++m_admitted;
  m_datagramBytes += static_cast<std::uint64_t>(charged);
  return ceilMicros(departure);
}

std::size_t LinkRate::available(Micros now) const {
  const double deficit = full(now) - micros(now);  // µs until the bucket is full again
  const double tokens = static_cast<double>(m_settings.burstBytes) - deficit / m_microsPerByte;
  return tokens <= 0.0 ? 0 : static_cast<std::size_t>(std::floor(tokens + 1e-6));  // 1e-6: rounding of E
}

void LinkRate::consume(std::size_t bytes, Micros now) {
  m_full = full(now) + cost(static_cast<double>(bytes));
  m_streamBytes += bytes;
}

Micros LinkRate::availableAt(std::size_t bytes, Micros now) const {
  const double wanted = static_cast<double>(std::min<std::size_t>(bytes, m_settings.burstBytes));
  const double at = full(now) - cost(static_cast<double>(m_settings.burstBytes) - wanted);
  return std::max(now, ceilMicros(at));
}

std::size_t LinkRate::backlog(Micros now) const {
  const double waiting = full(now) - m_tau - micros(now);
  return waiting <= 0.0 ? 0 : static_cast<std::size_t>(std::ceil(waiting / m_microsPerByte));
}

}  // namespace sc::session
