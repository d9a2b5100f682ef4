#include "session/engine/relay_verified_messages.h"

#include <algorithm>
#include <utility>

namespace sc::session {

RelayVerifiedMessages::RelayVerifiedMessages(QString sessionId, QByteArray pin, std::size_t capacity)
    : m_sessionId(std::move(sessionId)), m_pin(std::move(pin)), m_capacity(std::max<std::size_t>(1, capacity)) {}

bool RelayVerifiedMessages::contains(QByteArrayView message) const {
  // Newest first: the viewers of a process receive the same frame within a few milliseconds of one another.
  for (auto it = m_messages.rbegin(); it != m_messages.rend(); ++it) {
    if (QByteArrayView(*it) == message) {
      ++m_hits;
      return true;
    }
  }
  return false;
}

void RelayVerifiedMessages::remember(QByteArrayView message) {
  if (m_messages.size() == m_capacity) m_messages.pop_front();
  m_messages.emplace_back(message.toByteArray());
}

}  // namespace sc::session
