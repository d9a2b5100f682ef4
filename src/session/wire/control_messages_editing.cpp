// The lock and drag control messages (layouts in wire_format.h): LockMessage, LockNotice, Drag and Constraints.
// Declared in control_codec.h; dispatched by control_messages.cpp.
#include "session/wire/control_codec.h"
#include "session/wire/control_messages.h"

#include <cstdint>
#include <vector>

namespace sc::session {
namespace {

using detail::inRange;
using detail::readFinite;

void writeIds(ByteWriter& w, const std::vector<std::uint32_t>& ids) {
  w.u32(static_cast<std::uint32_t>(ids.size()));
  for (std::uint32_t id : ids) w.u32(id);
}
/// Reads a u32 count and that many ids; the running total must stay ≤ kMaxConstraintVertices.
bool readIds(ByteReader& r, std::vector<std::uint32_t>& ids, std::uint32_t& total) {
  const std::uint32_t count = r.u32();
  if (!r.ok() || count > kMaxConstraintVertices - total || qsizetype{4} * count > r.remaining()) return false;
  total += count;
  ids.resize(count);
  for (std::uint32_t& id : ids) id = r.u32();
  return r.ok();
}

}  // namespace

void write(ByteWriter& w, const LockMessage& m) {
  w.u8(static_cast<std::uint8_t>(m.kind));
  w.u32(m.epoch);
}
bool read(ByteReader& r, LockMessage& m) {
  const std::uint8_t kind = r.u8();
  m.kind = static_cast<LockRequestKind>(kind);
  m.epoch = r.u32();
  return inRange<std::uint8_t>(kind, 1, 3);
}

void write(ByteWriter& w, const LockNotice& m) {
  w.u8(static_cast<std::uint8_t>(m.kind));
  w.u32(m.peer);
  w.u32(m.epoch);
  w.u32(m.queuePosition);
  w.u8(static_cast<std::uint8_t>(m.reason));
  w.u8(static_cast<std::uint8_t>(m.waiting.size()));  // > kMaxPeers fails encodeControlMessage()'s check
  for (const PeerId peer : m.waiting) w.u32(peer);
}
bool read(ByteReader& r, LockNotice& m) {
  const std::uint8_t kind = r.u8();
  m.kind = static_cast<LockNoticeKind>(kind);
  m.peer = r.u32();
  m.epoch = r.u32();
  m.queuePosition = r.u32();
  const std::uint8_t reason = r.u8();
  m.reason = static_cast<LockReleaseReason>(reason);
  const int count = r.u8();
  if (count > kMaxPeers || (count > 0 && m.kind != LockNoticeKind::Waiting && m.kind != LockNoticeKind::Refused)) {
    return false;
  }
  m.waiting.resize(static_cast<std::size_t>(count));
  for (PeerId& peer : m.waiting) {
    peer = r.u32();
    if (!inRange<PeerId>(peer, 1, 0xffff)) return false;
  }
  return inRange<std::uint8_t>(kind, 1, kLockNoticeKindLast) && reason <= kLockReleaseReasonLast;
}

void write(ByteWriter& w, const Drag& m) {
  w.u32(m.epoch);
  w.u16(static_cast<std::uint16_t>(m.handles.size()));
  for (const HandleTransform& handle : m.handles) {
    w.u16(handle.handle);
    for (double value : handle.affine) w.f64(value);
  }
}
bool read(ByteReader& r, Drag& m) {
  m.epoch = r.u32();
  const int count = r.u16();
  if (m.epoch == kNoEpoch || count > kMaxHandles) return false;
  m.handles.resize(static_cast<std::size_t>(count));
  for (HandleTransform& handle : m.handles) {
    handle.handle = r.u16();
    for (double& value : handle.affine) {
      if (!readFinite(r, value)) return false;
    }
  }
  return true;
}

void write(ByteWriter& w, const Constraints& m) {
  w.u32(m.epoch);
  w.u16(static_cast<std::uint16_t>(m.groups.size()));
  for (const auto& group : m.groups) writeIds(w, group);
  writeIds(w, m.anchors);
}
bool read(ByteReader& r, Constraints& m) {
  m.epoch = r.u32();
  const int count = r.u16();
  if (m.epoch == kNoEpoch || count > kMaxHandles) return false;
  std::uint32_t total = 0;
  m.groups.resize(static_cast<std::size_t>(count));
  for (auto& group : m.groups) {
    if (!readIds(r, group, total) || group.empty()) return false;
  }
  return readIds(r, m.anchors, total);
}

}  // namespace sc::session
