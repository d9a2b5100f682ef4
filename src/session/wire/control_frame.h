#pragma once
// Splits a TCP byte stream into control frames (wire_format.h, "control messages") and decodes them.
// Bytes may arrive with arbitrary split points. Lengths are never trusted: a length of 0 or above
// kMaxControlMessageSize is reported as soon as its 4 bytes are in, before any body is buffered.

#include "session/wire/control_messages.h"

#include <QtCore/QByteArray>
#include <QtCore/QByteArrayView>

#include <optional>

namespace sc::session {

/// One per connection and direction. Not thread-safe. Buffered bytes stay below kControlHeaderSize +
/// kMaxControlMessageSize plus whatever the caller appends between calls to next(), so a caller drains next()
/// after every append().
class ControlFrameReader {
 public:
  /// Appends received bytes. Ignored once failed().
  void append(QByteArrayView bytes);

  /// The next frame: std::nullopt while it is incomplete (or after failure). Otherwise a decoded message
  /// (error None) or an error: Oversize makes the reader failed() for good (the stream cannot be resynchronised)
  /// and drops its buffer; UnknownType and Malformed consume exactly their frame (the protocol's rule is still to
  /// close the connection, see docs/protocol.md). Cost: O(frame size).
  std::optional<ControlDecodeResult> next();

  /// True after an Oversize frame.
  bool failed() const { return m_failed; }

  /// Bytes received but not yet returned as a frame.
  qsizetype buffered() const { return m_buffer.size() - m_position; }

 private:
  QByteArray m_buffer;
  qsizetype m_position = 0;  ///< start of the first unread frame in m_buffer
  bool m_failed = false;
};

}  // namespace sc::session
