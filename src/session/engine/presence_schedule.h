#pragma once
// PresenceSchedule: when a user's Presence goes out (issue 15), socket-free with the clock injected. At most one
// send per movingInterval (~30/s) while the presence changes, and one per idleInterval (~2/s) while it does not
// (a keep-alive, so that a late joiner sees everyone within idleInterval). Never more often than idleInterval
// when nothing changed. Cost: O(1) per call, no allocation.
//
// Use: offer() the current presence whenever it may have changed (camera moved, pointer moved) and when the timer
// armed at nextDue() fires; send it when offer() says so.

#include "session/engine/receiver_statistics.h"
#include "session/wire/control_messages.h"

#include <optional>

namespace sc::session {

struct PresenceScheduleOptions {
  Micros movingInterval{33'333};  ///< spacing of sends while the presence changes (30 per second)
  Micros idleInterval{500'000};   ///< spacing of sends while it does not (2 per second)
};

class PresenceSchedule {
 public:
  explicit PresenceSchedule(PresenceScheduleOptions options = {}) : m_options(options) {}

  /// The presence now is `current`: true when it must be sent now (the caller sends it; it counts as sent).
  /// Otherwise a changed value waits (pending) until movingInterval after the last send.
  bool offer(const Presence& current, Micros now);
  /// When offer() should be called again even if nothing else happens: the pending change's slot, or the next
  /// keep-alive; nullopt before the first send.
  [[nodiscard]] std::optional<Micros> nextDue() const;
  /// Forget what was sent (e.g. a new session): the next offer() sends at once.
  void reset() {
    m_lastSent.reset();
    m_pending = false;
  }
  [[nodiscard]] bool pending() const { return m_pending; }

 private:
  PresenceScheduleOptions m_options;
  std::optional<Presence> m_sent;  ///< the value last sent
  std::optional<Micros> m_lastSent;
  bool m_pending = false;  ///< a changed value waits for its slot
};

}  // namespace sc::session
