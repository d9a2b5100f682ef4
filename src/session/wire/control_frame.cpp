#include "session/wire/control_frame.h"

#include <QtCore/QtEndian>

namespace sc::session {

void ControlFrameReader::append(QByteArrayView bytes) {
  if (m_failed) return;
  if (m_position > 0 && m_position >= m_buffer.size() / 2) {  // compact: amortised O(1) per byte
    m_buffer.remove(0, m_position);
    m_position = 0;
  }
  m_buffer.append(bytes.data(), bytes.size());
}

std::optional<ControlDecodeResult> ControlFrameReader::next() {
  if (m_failed || buffered() < kControlLengthSize) return std::nullopt;
  const char* at = m_buffer.constData() + m_position;
  const std::uint32_t length = qFromBigEndian<std::uint32_t>(at);
  if (length == 0 || length > kMaxControlMessageSize) {
    m_failed = true;
    m_buffer.clear();
    m_position = 0;
    return ControlDecodeResult{ControlError::Oversize, {}};
  }
  const qsizetype frameSize = kControlLengthSize + qsizetype{length};
  if (buffered() < frameSize) return std::nullopt;
  const auto type = static_cast<std::uint8_t>(at[kControlLengthSize]);
  const QByteArrayView body(at + kControlHeaderSize, frameSize - kControlHeaderSize);
  ControlDecodeResult result = decodeControlMessage(type, body);  // copies what it keeps out of the buffer
  m_position += frameSize;
  return result;
}

}  // namespace sc::session
