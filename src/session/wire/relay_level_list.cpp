#include "session/wire/relay_level_list.h"

#include "session/wire/byte_io.h"
#include "session/wire/wire_format.h"

namespace sc::session {
namespace {
constexpr std::uint16_t kRelayMagic = 0x5343;  // relay_message.h
constexpr int kSha256Bytes = 32;
}  // namespace

const RelayLevelEntry* RelayLevelList::find(std::uint8_t index) const {
  for (const RelayLevelEntry& entry : levels) {
    if (entry.index == index) return &entry;
  }
  return nullptr;
}

QByteArray encodeRelayLevelListBody(const RelayLevelList& list) {
  QByteArray out;
  out.reserve(kRelayLevelsHeaderSize + kRelayLevelEntrySize * static_cast<qsizetype>(list.levels.size()));
  ByteWriter w(out);
  w.u16(kRelayMagic);
  w.u8(kRelayVersion);
  w.u8(static_cast<std::uint8_t>(RelayKind::Levels));
  w.u16(static_cast<std::uint16_t>(list.rowCount));
  w.u32(list.vertexCount);
  w.u32(list.chunkBytes);
  w.u8(list.total);
  w.u8(static_cast<std::uint8_t>(list.levels.size()));
  for (const RelayLevelEntry& entry : list.levels) {
    w.u8(entry.index);
    w.u32(entry.vertexCount);
    w.u32(entry.faceCount);
    w.u32(entry.payloadBytes);
    w.bytes(entry.payloadSha256.leftJustified(kSha256Bytes, '\0', true));
    w.bytes(entry.canonicalSha256.leftJustified(kSha256Bytes, '\0', true));
  }
  return out;
}

std::optional<RelayLevelList> decodeRelayLevelListBody(QByteArrayView body) {
  if (body.size() < kRelayLevelsHeaderSize) return std::nullopt;
  ByteReader in(body);
  if (in.u16() != kRelayMagic || in.u8() != kRelayVersion || in.u8() != static_cast<std::uint8_t>(RelayKind::Levels)) {
    return std::nullopt;
  }
  RelayLevelList list;
  list.rowCount = in.u16();
  list.vertexCount = in.u32();
  list.chunkBytes = in.u32();
  list.total = in.u8();
  const int count = in.u8();
  if (list.rowCount < 1 || list.rowCount > kMaxRows || list.vertexCount < 1 || list.chunkBytes < 1 ||
      list.chunkBytes > kMaxRelayChunkBytes || list.total < 1 || list.total > kMaxLevels || count > list.total ||
      in.remaining() != static_cast<qsizetype>(count) * kRelayLevelEntrySize) {
    return std::nullopt;
  }
  list.levels.reserve(static_cast<std::size_t>(count));
  for (int i = 0; i < count; ++i) {
    RelayLevelEntry entry;
    entry.index = in.u8();
    entry.vertexCount = in.u32();
    entry.faceCount = in.u32();
    entry.payloadBytes = in.u32();
    entry.payloadSha256 = in.bytes(kSha256Bytes);
    entry.canonicalSha256 = in.bytes(kSha256Bytes);
    const bool ascending = list.levels.empty() || list.levels.back().index < entry.index;
    if (!ascending || entry.index >= list.total || entry.vertexCount < 1 || entry.payloadBytes < 1 ||
        entry.payloadBytes > kMaxTransferSize) {
      return std::nullopt;
    }
    list.levels.push_back(std::move(entry));
  }
  if (!in.finished()) return std::nullopt;
  return list;
}

std::uint32_t relayChunkCount(std::uint32_t payloadBytes, std::uint32_t chunkBytes) {
  return static_cast<std::uint32_t>((std::uint64_t{payloadBytes} + chunkBytes - 1) / chunkBytes);
}

std::uint32_t relayChunkSize(std::uint32_t payloadBytes, std::uint32_t chunkBytes, std::uint32_t chunk) {
  const std::uint64_t start = std::uint64_t{chunk} * chunkBytes;
  if (start >= payloadBytes) return 0;
  return static_cast<std::uint32_t>(std::min<std::uint64_t>(chunkBytes, payloadBytes - start));
}

std::string relayLevelStream(const QString& sessionId) { return "SC_" + sessionId.toStdString() + "_LEVELS"; }
std::string relayLevelSubjects(const QString& sessionId) { return "sc." + sessionId.toStdString() + ".level.>"; }
std::string relayLevelChunkSubject(const QString& sessionId, std::uint8_t index, std::uint32_t chunk) {
  return "sc." + sessionId.toStdString() + ".level." + std::to_string(index) + "." + std::to_string(chunk);
}

}  // namespace sc::session
