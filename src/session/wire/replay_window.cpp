#include "session/wire/replay_window.h"

namespace sc::session {
namespace {
constexpr std::uint64_t kCycle = 65536;
constexpr std::uint64_t kHalfCycle = 32768;
}  // namespace

std::uint64_t ReplayWindow::extend(std::uint16_t wire) const {
  if (!m_initialised) return wire;
  const std::uint64_t candidate = (m_newest & ~(kCycle - 1)) | wire;
  if (candidate > m_newest + kHalfCycle && candidate >= kCycle) return candidate - kCycle;  // previous cycle
  if (candidate + kHalfCycle <= m_newest) return candidate + kCycle;                        // next cycle
  return candidate;
}

ReplayVerdict ReplayWindow::check(std::uint64_t sequence) const {
  if (!m_initialised || sequence > m_newest) return ReplayVerdict::Fresh;
  const std::uint64_t behind = m_newest - sequence;
  if (behind >= kWindowSize) return ReplayVerdict::Stale;
  return (m_bits >> behind) & 1u ? ReplayVerdict::Replayed : ReplayVerdict::Fresh;
}

void ReplayWindow::accept(std::uint64_t sequence) {
  if (!m_initialised) {
    m_initialised = true;
    m_newest = sequence;
    m_bits = 1;
    return;
  }
  if (sequence > m_newest) {
    const std::uint64_t ahead = sequence - m_newest;
    m_bits = ahead >= kWindowSize ? 0 : m_bits << ahead;
    m_bits |= 1;
    m_newest = sequence;
  } else if (m_newest - sequence < kWindowSize) {
    m_bits |= std::uint64_t{1} << (m_newest - sequence);
  }
}

}  // namespace sc::session
