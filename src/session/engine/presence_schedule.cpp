#include "session/engine/presence_schedule.h"

namespace sc::session {

bool PresenceSchedule::offer(const Presence& current, Micros now) {
  const bool changed = !m_sent || !(*m_sent == current);
  const bool due = !m_lastSent || now - *m_lastSent >= (changed ? m_options.movingInterval : m_options.idleInterval);
  m_pending = changed && !due;
  if (!due) return false;
  m_sent = current;
  m_lastSent = now;
  return true;
}

std::optional<Micros> PresenceSchedule::nextDue() const {
  if (!m_lastSent) return std::nullopt;
  return *m_lastSent + (m_pending ? m_options.movingInterval : m_options.idleInterval);
}

}  // namespace sc::session
