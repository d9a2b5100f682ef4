#pragma once
// Relay messages already found authentic, shared by several RelayReceivers of ONE thread that watch the same session
// pinned to the same host certificate (the fan-out experiment's viewers sharing a process: experiments/fanout). A
// message equal byte for byte to one verified before is authentic without a second ECDSA verify (≈ 55 µs saved per
// viewer and frame; the look-up compares sizes, then at most `capacity` memcmp of the message). A real viewer is one
// receiver per process and never needs this. Pure; not thread-safe.

#include <QtCore/QByteArray>
#include <QtCore/QByteArrayView>
#include <QtCore/QString>

#include <cstddef>
#include <cstdint>
#include <deque>

namespace sc::session {

class RelayVerifiedMessages {
 public:
  /// @param sessionId, pin  the session and the host certificate's SHA-256 the receivers using it pin; a receiver
  ///   with another session or pin ignores it.
  RelayVerifiedMessages(QString sessionId, QByteArray pin, std::size_t capacity = 16);

  [[nodiscard]] bool appliesTo(const QString& sessionId, const QByteArray& pin) const {
    return sessionId == m_sessionId && pin == m_pin;
  }
  /// Whether `message` was remembered (verified) before, byte for byte.
  [[nodiscard]] bool contains(QByteArrayView message) const;
  /// Remembers a message its receiver verified; the oldest beyond `capacity` is forgotten.
  void remember(QByteArrayView message);
  /// Verifies saved so far (look-ups that found the message).
  [[nodiscard]] std::int64_t hits() const { return m_hits; }

 private:
  QString m_sessionId;
  QByteArray m_pin;
  std::size_t m_capacity;
  std::deque<QByteArray> m_messages;  ///< newest last
  mutable std::int64_t m_hits = 0;
};

}  // namespace sc::session
