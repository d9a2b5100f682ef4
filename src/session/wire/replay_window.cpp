#include "session/wire/replay_window.h"

namespace sc::session {
namespace {

int serialDistance(std::uint16_t from, std::uint16_t to) {
  return static_cast<std::int16_t>(static_cast<std::uint16_t>(to - from));
}

}  // namespace

ReplayVerdict ReplayWindow::check(std::uint16_t sequence) const {
  if (!m_initialised) return ReplayVerdict::Fresh;
  const int d = serialDistance(m_newest, sequence);
  if (d > 0) return ReplayVerdict::Fresh;
  if (d <= -kWindowSize) return ReplayVerdict::Stale;
  return (m_bits >> (-d)) & 1u ? ReplayVerdict::Replayed : ReplayVerdict::Fresh;
}

void ReplayWindow::accept(std::uint16_t sequence) {
  if (!m_initialised) {
    m_initialised = true;
    m_newest = sequence;
    m_bits = 1;
    return;
  }
  const int d = serialDistance(m_newest, sequence);
  if (d > 0) {
    m_bits = d >= kWindowSize ? 0 : m_bits << d;
    m_bits |= 1;
    m_newest = sequence;
  } else if (d > -kWindowSize) {
    m_bits |= std::uint64_t{1} << (-d);
  }
}

}  // namespace sc::session
