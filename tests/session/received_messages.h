#pragma once
// takeReceived(): the wait-and-take of a test peer's received control messages (RawControlPeer, HostileHost).

#include "session/wire/control_messages.h"

#include <QtTest/QTest>

#include <optional>
#include <variant>
#include <vector>

namespace sc::session::testing {

/// Waits (running the event loop) for the first message of type T in `received`, removes and returns it; nullopt
/// after `timeoutMs`. `received` is filled by the caller's socket slots while this waits.
template <typename T>
std::optional<T> takeReceived(std::vector<ControlMessage>& received, int timeoutMs) {
  std::optional<T> found;
  (void)QTest::qWaitFor(
      [&] {
        for (auto it = received.begin(); it != received.end(); ++it) {
          if (std::holds_alternative<T>(*it)) {
            found = std::get<T>(*it);
            received.erase(it);
            return true;
          }
        }
        return false;
      },
      timeoutMs);
  return found;
}

}  // namespace sc::session::testing
