#pragma once
// Hands NATS messages from a cnats thread to a Qt object's thread (issue 18): a mutex-protected queue of at most
// `limit` messages (when full the oldest is dropped and counted: latest wins, nothing queues without bound) and at
// most one queued wake-up at a time, posted with QMetaObject::invokeMethod(receiver, …, Qt::QueuedConnection)
// (Qt drops it once the receiver is gone). push() is the only call made on the cnats thread.

#include <QtCore/QByteArray>
#include <QtCore/QByteArrayView>

#include <cstdint>
#include <deque>
#include <functional>
#include <mutex>

class QObject;

namespace sc::session {

class NatsInbox {
 public:
  /// @param limit  messages kept at most, ≥ 1.
  /// @param receiver  the object whose thread runs `wake`; must outlive every push().
  /// @param wake  called on the receiver's thread after push(); it should call take().
  NatsInbox(int limit, QObject* receiver, std::function<void()> wake);

  /// Any thread: queues a copy of `message`. Cost: one copy, O(1).
  void push(QByteArrayView message);
  /// The receiver's thread: everything queued, oldest first.
  std::deque<QByteArray> take();
  /// Messages dropped because `limit` were waiting.
  [[nodiscard]] std::int64_t dropped() const;

 private:
  const int m_limit;
  QObject* m_receiver;
  std::function<void()> m_wake;
  mutable std::mutex m_mutex;
  std::deque<QByteArray> m_messages;
  std::int64_t m_dropped = 0;
  bool m_posted = false;
};

}  // namespace sc::session
