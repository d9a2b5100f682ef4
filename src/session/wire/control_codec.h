#pragma once
// Internal to the control-message codecs (control_messages.cpp, control_messages_collab.cpp): the text and number
// readers every message uses, and the write()/read() pairs defined outside control_messages.cpp (found by argument-
// dependent lookup from its dispatch). Not part of the wire API: callers use control_messages.h. Cost: O(size).

#include "session/wire/byte_io.h"

#include <QtCore/QString>

namespace sc::session {

// Declared here without control_messages.h, which includes nothing of this header's (no include loop).
struct LockMessage;
struct LockNotice;
struct Drag;
struct Constraints;
struct StrokeEnd;
struct EditRequest;
struct EditLog;
struct Presence;
namespace detail {

enum class Prefix { U8, U16 };

template <typename T>
bool inRange(T value, T low, T high) {
  return value >= low && value <= high;
}

/// Writes `text` as UTF-8 with a u8 or u16 length; an over-long text wraps its prefix and then fails the
/// round-trip check in encodeControlMessage().
void writeText(ByteWriter& writer, const QString& text, Prefix prefix);
/// Reads a length-prefixed UTF-8 text of at most maxBytes; false on short input, over-long or invalid UTF-8.
bool readText(ByteReader& reader, QString& text, Prefix prefix, int maxBytes);
/// Reads an f64; false when it is not finite.
bool readFinite(ByteReader& reader, double& value);

}  // namespace detail

// control_messages_editing.cpp: read() checks ranges, the caller checks exact consumption.
void write(ByteWriter& w, const LockMessage& m);
bool read(ByteReader& r, LockMessage& m);
void write(ByteWriter& w, const LockNotice& m);
bool read(ByteReader& r, LockNotice& m);
void write(ByteWriter& w, const Drag& m);
bool read(ByteReader& r, Drag& m);
void write(ByteWriter& w, const Constraints& m);
bool read(ByteReader& r, Constraints& m);

// control_messages_collab.cpp: read() checks ranges, the caller checks exact consumption.
void write(ByteWriter& w, const StrokeEnd& m);
bool read(ByteReader& r, StrokeEnd& m);
void write(ByteWriter& w, const EditRequest& m);
bool read(ByteReader& r, EditRequest& m);
void write(ByteWriter& w, const EditLog& m);
bool read(ByteReader& r, EditLog& m);
void write(ByteWriter& w, const Presence& m);
bool read(ByteReader& r, Presence& m);

}  // namespace sc::session
