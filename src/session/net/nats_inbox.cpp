#include "session/net/nats_inbox.h"

#include <QtCore/QMetaObject>
#include <QtCore/QObject>

#include <algorithm>
#include <utility>

namespace sc::session {

NatsInbox::NatsInbox(int limit, QObject* receiver, std::function<void()> wake)
    : m_limit(std::max(1, limit)), m_receiver(receiver), m_wake(std::move(wake)) {}

void NatsInbox::push(QByteArrayView message) {
  const std::lock_guard lock(m_mutex);
  if (static_cast<int>(m_messages.size()) >= m_limit) {
    m_messages.pop_front();
    ++m_dropped;
  }
  m_messages.emplace_back(message.toByteArray());
  if (m_posted) return;
  m_posted = true;
  QMetaObject::invokeMethod(m_receiver, m_wake, Qt::QueuedConnection);
}

std::deque<QByteArray> NatsInbox::take() {
  const std::lock_guard lock(m_mutex);
  m_posted = false;
  std::deque<QByteArray> out;
  out.swap(m_messages);
  return out;
}

std::int64_t NatsInbox::dropped() const {
  const std::lock_guard lock(m_mutex);
  return m_dropped;
}

}  // namespace sc::session
