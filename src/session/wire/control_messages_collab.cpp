// The control messages of editing together (protocol version 4; layouts in wire_format.h): StrokeEnd, EditRequest,
// EditLog and Presence. Declared in control_codec.h; dispatched by control_messages.cpp.
#include "session/wire/control_codec.h"
#include "session/wire/control_messages.h"

#include <cmath>

namespace sc::session {

using detail::inRange;
using detail::Prefix;
using detail::readFinite;
using detail::readText;
using detail::writeText;

void write(ByteWriter& w, const StrokeEnd& m) { w.u32(m.epoch); }
bool read(ByteReader& r, StrokeEnd& m) {
  m.epoch = r.u32();
  return m.epoch != kNoEpoch;
}

void write(ByteWriter& w, const EditRequest& m) { w.u8(static_cast<std::uint8_t>(m.action)); }
bool read(ByteReader& r, EditRequest& m) {
  const std::uint8_t action = r.u8();
  m.action = static_cast<EditAction>(action);
  return inRange<std::uint8_t>(action, 1, 2);
}

void write(ByteWriter& w, const EditLog& m) {
  w.u8(static_cast<std::uint8_t>(m.steps.size()));
  for (const EditLogEntry& entry : m.steps) {
    w.u32(entry.step);
    w.u32(entry.author);
    w.u32(entry.undoneBy);
    w.u8(entry.redoable ? 1 : 0);
    writeText(w, entry.authorName, Prefix::U8);
  }
}
bool read(ByteReader& r, EditLog& m) {
  const int count = r.u8();
  if (count > kMaxEditLogSteps) return false;
  m.steps.resize(static_cast<std::size_t>(count));
  std::uint32_t previous = 0;
  for (EditLogEntry& entry : m.steps) {
    entry.step = r.u32();
    entry.author = r.u32();
    entry.undoneBy = r.u32();
    const std::uint8_t redoable = r.u8();
    entry.redoable = redoable == 1;
    if (!r.ok() || entry.step <= previous || entry.author > 0xffff || entry.undoneBy > 0xffff || redoable > 1 ||
        (entry.redoable && entry.undoneBy == kNoPeer) || !readText(r, entry.authorName, Prefix::U8, kMaxNameBytes)) {
      return false;
    }
    previous = entry.step;
  }
  return true;
}

namespace {

constexpr std::uint8_t kPresencePointer = 0x01;
constexpr std::uint8_t kPresenceDragging = 0x02;
constexpr std::uint8_t kPresenceHandle = 0x04;

void writePoint(ByteWriter& w, const Presence::Point& point) {
  for (double v : point) w.f64(v);
}
bool readPoint(ByteReader& r, Presence::Point& point) {
  for (double& v : point) {
    if (!readFinite(r, v) || std::abs(v) > kMaxPresenceCoord) return false;
  }
  return true;
}

}  // namespace

void write(ByteWriter& w, const Presence& m) {
  w.u32(m.author);
  w.u8(static_cast<std::uint8_t>((m.pointerOn ? kPresencePointer : 0) | (m.dragging ? kPresenceDragging : 0) |
                                 (m.handleOn ? kPresenceHandle : 0)));
  for (const Presence::Point* point : {&m.eye, &m.target, &m.up, &m.pointer, &m.handle}) writePoint(w, *point);
}
bool read(ByteReader& r, Presence& m) {
  m.author = r.u32();
  const std::uint8_t flags = r.u8();
  if (m.author > 0xffff || (flags & ~(kPresencePointer | kPresenceDragging | kPresenceHandle)) != 0) return false;
  m.pointerOn = (flags & kPresencePointer) != 0;
  m.dragging = (flags & kPresenceDragging) != 0;
  m.handleOn = (flags & kPresenceHandle) != 0;
  for (Presence::Point* point : {&m.eye, &m.target, &m.up, &m.pointer, &m.handle}) {
    if (!readPoint(r, *point)) return false;
  }
  // one encoding per value
  return (m.pointerOn || m.pointer == Presence::Point{}) && (m.handleOn || m.handle == Presence::Point{});
}

}  // namespace sc::session
