// Tests for the Presence control message (wire_format.h, 0x55): layout, limits and malformed bodies. No sockets.
#include "session/wire/control_messages.h"

#include <gtest/gtest.h>

#include <QtCore/QtEndian>

#include <bit>
#include <cmath>
#include <limits>

namespace sc::session {
namespace {

Presence samplePresence() {
  return Presence{2, {1.0, 2.0, 3.0}, {0.5, 0.0, -0.5}, {0.0, 1.0, 0.0}, true, {0.1, 0.2, 0.3}, false};
}

/// The encoded body (without the 5-byte frame header) of `presence`.
QByteArray body(const Presence& presence) {
  const QByteArray frame = encodeControlMessage(presence);
  return frame.isEmpty() ? frame : frame.sliced(kControlHeaderSize);
}

ControlError decodeError(const QByteArray& bytes) {
  return decodeControlMessage(static_cast<std::uint8_t>(MessageType::Presence), bytes).error;
}

/// `bytes` with the f64 at `offset` replaced by `value`.
QByteArray withDouble(QByteArray bytes, int offset, double value) {
  qToBigEndian(std::bit_cast<std::uint64_t>(value), bytes.data() + offset);
  return bytes;
}

TEST(PresenceMessage, LayoutRoundTrip) {
  const Presence presence = samplePresence();
  const QByteArray frame = encodeControlMessage(presence);
  ASSERT_EQ(frame.size(), kControlHeaderSize + kPresenceSize);
  EXPECT_EQ(static_cast<std::uint8_t>(frame[4]), 0x55);
  const QByteArray bytes = frame.sliced(kControlHeaderSize);
  EXPECT_EQ(qFromBigEndian<std::uint32_t>(bytes.constData()), 2u);                               // author
  EXPECT_EQ(static_cast<std::uint8_t>(bytes[4]), 0x01);                                          // pointer flag only
  EXPECT_EQ(std::bit_cast<double>(qFromBigEndian<std::uint64_t>(bytes.constData() + 5)), 1.0);   // eye.x
  EXPECT_EQ(std::bit_cast<double>(qFromBigEndian<std::uint64_t>(bytes.constData() + 29)), 0.5);  // target.x
  EXPECT_EQ(std::bit_cast<double>(qFromBigEndian<std::uint64_t>(bytes.constData() + 61)), 1.0);  // up.y
  EXPECT_EQ(std::bit_cast<double>(qFromBigEndian<std::uint64_t>(bytes.constData() + 93)), 0.3);  // pointer.z
  const ControlDecodeResult decoded = decodeControlMessage(0x55, bytes);
  ASSERT_EQ(decoded.error, ControlError::None);
  EXPECT_EQ(std::get<Presence>(decoded.message), presence);

  Presence dragging = presence;
  dragging.dragging = true;
  EXPECT_EQ(static_cast<std::uint8_t>(body(dragging)[4]), 0x03);
  Presence noPointer = presence;
  noPointer.pointerOn = false;
  noPointer.pointer = {};
  EXPECT_EQ(static_cast<std::uint8_t>(body(noPointer)[4]), 0x00);
  EXPECT_EQ(std::get<Presence>(decodeControlMessage(0x55, body(noPointer)).message), noPointer);

  Presence withHandle = presence;  // since version 5: the centroid of the painted handle
  withHandle.handleOn = true;
  withHandle.handle = {-0.75, 0.5, 2.0};
  const QByteArray handleBytes = body(withHandle);
  EXPECT_EQ(static_cast<std::uint8_t>(handleBytes[4]), 0x05);
  EXPECT_EQ(std::bit_cast<double>(qFromBigEndian<std::uint64_t>(handleBytes.constData() + 101)), -0.75);  // handle.x
  EXPECT_EQ(std::get<Presence>(decodeControlMessage(0x55, handleBytes).message), withHandle);
  EXPECT_EQ(decodeError(withDouble(body(presence), 101, 1.0)), ControlError::Malformed)
      << "a handle point without its flag has two encodings: refused";
}

TEST(PresenceMessage, ValuesBreakingLimitsDoNotEncode) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  for (double bad : {nan, inf, -inf, 2 * kMaxPresenceCoord, -1.5 * kMaxPresenceCoord}) {
    Presence p = samplePresence();
    p.eye[1] = bad;
    EXPECT_TRUE(encodeControlMessage(p).isEmpty()) << bad;
    p = samplePresence();
    p.pointer[2] = bad;
    EXPECT_TRUE(encodeControlMessage(p).isEmpty()) << bad;
  }
  Presence author = samplePresence();
  author.author = 65536;  // peer ids are 16-bit
  EXPECT_TRUE(encodeControlMessage(author).isEmpty());
  Presence strayPointer = samplePresence();
  strayPointer.pointerOn = false;  // a pointer position without the flag has two encodings: refused
  EXPECT_TRUE(encodeControlMessage(strayPointer).isEmpty());
  Presence edge = samplePresence();
  edge.target = {kMaxPresenceCoord, -kMaxPresenceCoord, 0.0};
  EXPECT_FALSE(encodeControlMessage(edge).isEmpty());
}

TEST(PresenceMessage, MalformedBodiesAreRejected) {
  const QByteArray good = body(samplePresence());
  ASSERT_EQ(good.size(), kPresenceSize);
  EXPECT_EQ(decodeError(good), ControlError::None);
  for (int size = 0; size < kPresenceSize; ++size) EXPECT_EQ(decodeError(good.first(size)), ControlError::Malformed);
  EXPECT_EQ(decodeError(good + QByteArray(1, '\0')), ControlError::Malformed);  // trailing byte
  for (int bit = 3; bit < 8; ++bit) {                                           // reserved flag bits
    QByteArray flags = good;
    flags[4] = static_cast<char>(flags[4] | (1 << bit));
    EXPECT_EQ(decodeError(flags), ControlError::Malformed) << bit;
  }
  for (int offset = 5; offset < kPresenceSize; offset += 8) {  // every coordinate: NaN, ±inf, out of bounds
    for (double bad : {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity(),
                       -std::numeric_limits<double>::infinity(), 1e10}) {
      EXPECT_EQ(decodeError(withDouble(good, offset, bad)), ControlError::Malformed) << offset;
    }
  }
  QByteArray bigAuthor = good;
  qToBigEndian<std::uint32_t>(0x10000, bigAuthor.data());
  EXPECT_EQ(decodeError(bigAuthor), ControlError::Malformed);
}

}  // namespace
}  // namespace sc::session
