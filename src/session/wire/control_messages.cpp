#include "session/wire/control_messages.h"

#include "session/wire/byte_io.h"
#include "session/wire/control_codec.h"

#include <cmath>
#include <utility>

namespace sc::session {
namespace {

using detail::inRange;
using detail::Prefix;
using detail::readFinite;
using detail::readText;
using detail::writeText;

// === one write()/read() pair per message; read() checks ranges, the caller checks exact consumption. The lock and
// drag messages are in control_messages_editing.cpp, those of editing together (version 4) in
// control_messages_collab.cpp.

void write(ByteWriter& w, const Hello& m) {
  w.u16(kMagic);
  w.u8(m.version);
  writeText(w, m.displayName, Prefix::U8);
}
bool read(ByteReader& r, Hello& m) {
  const std::uint16_t magic = r.u16();
  m.version = r.u8();
  if (!r.ok() || magic != kMagic) return false;
  if (m.version != kProtocolVersion) {  // another version's Hello may differ after the version byte: skip it
    r.bytes(r.remaining());
    return true;
  }
  return readText(r, m.displayName, Prefix::U8, kMaxNameBytes);
}

void write(ByteWriter& w, const Refused& m) {
  w.u8(static_cast<std::uint8_t>(m.reason));
  w.u8(m.hostVersion);
  writeText(w, m.text, Prefix::U16);
}
bool read(ByteReader& r, Refused& m) {
  const std::uint8_t reason = r.u8();
  m.reason = static_cast<RefuseReason>(reason);
  m.hostVersion = r.u8();
  return inRange<std::uint8_t>(reason, 1, kRefuseReasonLast) && readText(r, m.text, Prefix::U16, kMaxTextBytes);
}

void write(ByteWriter& w, const Challenge& m) {
  w.bytes(m.nonce);
  w.bytes(m.salt);
  w.u32(m.iterations);
}
bool read(ByteReader& r, Challenge& m) {
  m.nonce = r.bytes(kNonceSize);
  m.salt = r.bytes(kSaltSize);
  m.iterations = r.u32();
  return inRange<std::uint32_t>(m.iterations, 1, kMaxPbkdf2Iterations);
}

void write(ByteWriter& w, const ChallengeResponse& m) { w.bytes(m.mac); }
bool read(ByteReader& r, ChallengeResponse& m) {
  m.mac = r.bytes(kMacSize);
  return true;
}

void write(ByteWriter& w, const Welcome& m) {
  w.u32(m.peerId);
  w.bytes(m.datagramKey);
  w.bytes(m.pathToken);
  w.u16(m.rowCount);
  w.u32(m.vertexCount);
  w.u16(m.udpPort);
}
bool read(ByteReader& r, Welcome& m) {
  m.peerId = r.u32();
  m.datagramKey = r.bytes(kDatagramKeySize);
  m.pathToken = r.bytes(kPathTokenSize);
  m.rowCount = r.u16();
  m.vertexCount = r.u32();
  m.udpPort = r.u16();
  return inRange<PeerId>(m.peerId, 1, 0xffff) && inRange<int>(m.rowCount, 1, kMaxRows) && m.vertexCount >= 1 &&
         m.udpPort >= 1;
}

void write(ByteWriter& w, const ModelBegin& m) {
  w.u32(m.transferId);
  w.u8(static_cast<std::uint8_t>(m.kind));
  w.u32(m.vertexCount);
  w.u32(m.totalSize);
  w.bytes(m.sha256);
}
bool read(ByteReader& r, ModelBegin& m) {
  m.transferId = r.u32();
  const std::uint8_t kind = r.u8();
  m.kind = static_cast<TransferKind>(kind);
  m.vertexCount = r.u32();
  m.totalSize = r.u32();
  m.sha256 = r.bytes(kChecksumSize);
  return m.transferId >= 1 && inRange<std::uint8_t>(kind, 1, 2) && m.vertexCount >= 1 &&
         inRange<std::uint32_t>(m.totalSize, 1, kMaxTransferSize);
}

void write(ByteWriter& w, const ModelChunk& m) {
  w.u32(m.transferId);
  w.u32(m.offset);
  w.u32(m.totalSize);
  w.u32(static_cast<std::uint32_t>(m.bytes.size()));
  w.bytes(m.bytes);
}
bool read(ByteReader& r, ModelChunk& m) {
  m.transferId = r.u32();
  m.offset = r.u32();
  m.totalSize = r.u32();
  const std::uint32_t size = r.u32();
  if (!inRange<std::uint32_t>(size, 1, kMaxChunkBytes)) return false;
  m.bytes = r.bytes(size);
  const std::uint64_t end = std::uint64_t{m.offset} + size;
  return m.transferId >= 1 && m.totalSize <= kMaxTransferSize && end <= m.totalSize;
}

void write(ByteWriter& w, const ResolutionRequest& m) { w.u32(m.vertexCount); }
bool read(ByteReader& r, ResolutionRequest& m) {
  m.vertexCount = r.u32();
  return true;
}

void write(ByteWriter& w, const PeerList& m) {
  w.u16(static_cast<std::uint16_t>(m.peers.size()));
  for (const PeerInfo& peer : m.peers) {
    w.u32(peer.peerId);
    w.u32(peer.vertexCount);
    writeText(w, peer.name, Prefix::U8);
  }
}
bool read(ByteReader& r, PeerList& m) {
  const int count = r.u16();
  if (count > kMaxPeers) return false;
  m.peers.resize(static_cast<std::size_t>(count));
  for (PeerInfo& peer : m.peers) {
    peer.peerId = r.u32();
    peer.vertexCount = r.u32();
    if (!inRange<PeerId>(peer.peerId, 1, 0xffff) || !readText(r, peer.name, Prefix::U8, kMaxNameBytes)) return false;
  }
  return true;
}

void write(ByteWriter& w, const Keyframe& m) {
  w.u32(m.frame);
  w.u16(static_cast<std::uint16_t>(m.z.size() / 3));
  for (double value : m.z) w.f64(value);
}
bool read(ByteReader& r, Keyframe& m) {
  m.frame = r.u32();
  const int rows = r.u16();
  if (!inRange(rows, 1, kMaxRows) || r.remaining() != qsizetype{24} * rows) return false;
  m.z.resize(static_cast<std::size_t>(3 * rows));
  for (double& value : m.z) {
    if (!readFinite(r, value)) return false;
  }
  return true;
}

void write(ByteWriter& w, const Leave& m) {
  w.u8(static_cast<std::uint8_t>(m.reason));
  writeText(w, m.text, Prefix::U16);
}
bool read(ByteReader& r, Leave& m) {
  const std::uint8_t reason = r.u8();
  m.reason = static_cast<LeaveReason>(reason);
  return reason <= kLeaveReasonLast && readText(r, m.text, Prefix::U16, kMaxTextBytes);
}

void write(ByteWriter& w, const Heartbeat& m) { w.u32(m.sequence); }
bool read(ByteReader& r, Heartbeat& m) {
  m.sequence = r.u32();
  return true;
}

void write(ByteWriter& w, const StatsReport& m) {
  w.u32(m.vertexCount);
  w.u32(m.framesApplied);
  for (std::uint64_t v : {m.received, m.lost, m.late, m.dropped}) w.u64(v);
  for (double v : {m.lossFraction, m.jitterMs, m.payloadKbpsIn, m.wireKbpsIn, m.framesPerSecond, m.latencyP50Ms,
                   m.latencyP99Ms, m.hdMaxPct, m.hdMeanPct, m.hdLastPct}) {
    w.f64(v);
  }
}
bool read(ByteReader& r, StatsReport& m) {
  m.vertexCount = r.u32();
  m.framesApplied = r.u32();
  for (std::uint64_t* v : {&m.received, &m.lost, &m.late, &m.dropped}) *v = r.u64();
  for (double* v : {&m.lossFraction, &m.jitterMs, &m.payloadKbpsIn, &m.wireKbpsIn, &m.framesPerSecond, &m.latencyP50Ms,
                    &m.latencyP99Ms, &m.hdMaxPct, &m.hdMeanPct, &m.hdLastPct}) {
    if (!readFinite(r, *v) || *v < 0.0) return false;
  }
  return true;
}

void write(ByteWriter& w, const LevelList& m) {
  w.u8(m.total);
  w.u8(static_cast<std::uint8_t>(m.levels.size()));
  for (const LevelInfo& level : m.levels) {
    w.u8(level.levelId);
    w.u32(level.vertexCount);
    w.u32(level.faceCount);
    w.u32(level.payloadBytes);
  }
}
bool read(ByteReader& r, LevelList& m) {
  m.total = r.u8();
  const int count = r.u8();
  if (!inRange<int>(m.total, 1, kMaxLevels) || count > m.total) return false;
  m.levels.resize(static_cast<std::size_t>(count));
  int previousId = -1;
  for (LevelInfo& level : m.levels) {
    level.levelId = r.u8();
    level.vertexCount = r.u32();
    level.faceCount = r.u32();
    level.payloadBytes = r.u32();
    if (level.levelId >= m.total || level.levelId <= previousId || level.vertexCount == 0 || level.faceCount == 0 ||
        !inRange<std::uint32_t>(level.payloadBytes, 1, kMaxTransferSize)) {
      return false;
    }
    previousId = level.levelId;
  }
  return true;
}

// === dispatch: variant alternative I has wire type kFirstControlType + I.

constexpr std::size_t kControlTypeCount = std::variant_size_v<ControlMessage>;
static_assert(kFirstControlType + kControlTypeCount == static_cast<std::size_t>(MessageType::ControlEnd));
static_assert(std::is_same_v<std::variant_alternative_t<0, ControlMessage>, Hello>);
static_assert(std::is_same_v<std::variant_alternative_t<14, ControlMessage>, Heartbeat>);
static_assert(std::is_same_v<std::variant_alternative_t<16, ControlMessage>, StatsReport>);
static_assert(std::is_same_v<std::variant_alternative_t<17, ControlMessage>, LevelList>);
static_assert(std::is_same_v<std::variant_alternative_t<20, ControlMessage>, EditLog>);
static_assert(std::is_same_v<std::variant_alternative_t<21, ControlMessage>, Presence>);

template <typename T>
ControlDecodeResult decodeAs(QByteArrayView body) {
  ByteReader reader(body);
  T value;
  if (!read(reader, value) || !reader.finished()) return {ControlError::Malformed, {}};
  return {ControlError::None, ControlMessage{std::move(value)}};
}

template <std::size_t... I>
constexpr auto makeDecoders(std::index_sequence<I...>) {
  return std::array<ControlDecodeResult (*)(QByteArrayView), sizeof...(I)>{
      &decodeAs<std::variant_alternative_t<I, ControlMessage>>...};
}
constexpr auto kDecoders = makeDecoders(std::make_index_sequence<kControlTypeCount>{});

}  // namespace

const LevelInfo* closestLevel(const LevelList& list, std::uint32_t wanted) {
  const LevelInfo* best = nullptr;
  const auto distance = [wanted](std::uint32_t v) { return v > wanted ? v - wanted : wanted - v; };
  for (const LevelInfo& level : list.levels) {
    if (best == nullptr) {
      best = &level;
    } else if (wanted == 0) {
      if (level.vertexCount > best->vertexCount) best = &level;
    } else if (distance(level.vertexCount) < distance(best->vertexCount) ||
               (distance(level.vertexCount) == distance(best->vertexCount) && level.vertexCount > best->vertexCount)) {
      best = &level;
    }
  }
  return best;
}

MessageType messageType(const ControlMessage& message) {
  return static_cast<MessageType>(kFirstControlType + message.index());
}

QByteArray encodeControlMessage(const ControlMessage& message) {
  QByteArray frame;
  ByteWriter writer(frame);
  writer.u32(0);  // patched below
  writer.u8(static_cast<std::uint8_t>(messageType(message)));
  std::visit([&writer](const auto& value) { write(writer, value); }, message);
  const qsizetype length = frame.size() - kControlLengthSize;
  if (length > qsizetype{kMaxControlMessageSize}) return {};
  // One source of truth for the limits: a value is encodable exactly when its bytes decode back to it.
  const ControlDecodeResult check = decodeControlMessage(static_cast<std::uint8_t>(messageType(message)),
                                                         QByteArrayView(frame).sliced(kControlHeaderSize));
  if (check.error != ControlError::None || !(check.message == message)) return {};
  qToBigEndian(static_cast<std::uint32_t>(length), frame.data());
  return frame;
}

ControlDecodeResult decodeControlMessage(std::uint8_t type, QByteArrayView body) {
  if (type < kFirstControlType || type >= static_cast<std::uint8_t>(MessageType::ControlEnd)) {
    return {ControlError::UnknownType, {}};
  }
  return kDecoders[type - kFirstControlType](body);
}

const char* toString(ControlError error) {
  switch (error) {
    case ControlError::None:
      return "none";
    case ControlError::Oversize:
      return "oversize";
    case ControlError::UnknownType:
      return "unknown-type";
    case ControlError::Malformed:
      return "malformed";
    case ControlError::Count:
      break;
  }
  return "?";
}

}  // namespace sc::session
