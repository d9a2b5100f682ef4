#pragma once
// Level payloads through the relay (issue 18 item 1; docs/protocol.md, "Relay through NATS", "Levels in a
// stream"): the host publishes each level payload ONCE, exactly the bytes the TLS path's ModelBegin/ModelChunk
// transfer carries (compressed, level_codec.h, or canonical for tiny levels), cut into chunks of `chunkBytes` on the
// JetStream stream `SC_<sid>_LEVELS`, subject `sc.<sid>.level.<index>.<chunk>` (one message kept per subject), and a
// signed list of what it published under the KV key `levels` of the session's bucket. A viewer trusts only the
// list (signed with the host's TLS identity key, like every relay message): the broker may drop, delay or replace
// chunks, and the viewer then refuses the level (the payload's SHA-256, then the decoded payload's, are in the list).
//
// Levels body (kind 4, relay_message.h's header and trailer; integers big-endian):
//
//  offset size    field
//  ------ ------- -----------------------------------------------------------------------------------------------
//     0    4      magic 0x5343, version kRelayVersion, kind 4
//     4    2      rowCount      m of the session, 1..kMaxRows
//     6    4      vertexCount   n of the session, ≥ 1
//    10    4      chunkBytes    c, 1..kMaxRelayChunkBytes: every chunk but a level's last has exactly c bytes
//    14    1      total         levels in the host's ladder (listed or not), 1..kMaxLevels
//    15    1      count         k levels listed, ≤ total, index strictly ascending
//    16   77k     per level: u8 index (0 = full model, i = i-th ladder level; < total), u32 n', u32 f',
//                 u32 payloadBytes (as published, 1..kMaxTransferSize), 32 B SHA-256 of the payload as published,
//                 32 B SHA-256 of the decoded (canonical) payload (= ModelBegin::sha256 on the TLS path)
//
// Cost: O(k); at most 16 + 77·16 = 1,248 bytes plus the trailer.

#include "session/wire/relay_message.h"

#include <QtCore/QByteArray>
#include <QtCore/QByteArrayView>
#include <QtCore/QString>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace sc::session {

inline constexpr std::uint32_t kMaxRelayChunkBytes = 1u << 20;  ///< NATS' default max_payload
inline constexpr int kRelayLevelEntrySize = 77;
inline constexpr int kRelayLevelsHeaderSize = 16;

/// One published level.
struct RelayLevelEntry {
  std::uint8_t index = 0;
  std::uint32_t vertexCount = 0;
  std::uint32_t faceCount = 0;
  std::uint32_t payloadBytes = 0;
  QByteArray payloadSha256;    ///< 32 bytes: the bytes on the stream
  QByteArray canonicalSha256;  ///< 32 bytes: the decoded payload
  friend bool operator==(const RelayLevelEntry&, const RelayLevelEntry&) = default;
};

/// The `levels` value.
struct RelayLevelList {
  int rowCount = 0;
  std::uint32_t vertexCount = 0;
  std::uint32_t chunkBytes = 0;
  std::uint8_t total = 0;
  std::vector<RelayLevelEntry> levels;  ///< index ascending
  [[nodiscard]] const RelayLevelEntry* find(std::uint8_t index) const;
  friend bool operator==(const RelayLevelList&, const RelayLevelList&) = default;
};

/// The unsigned body (sign it with RelaySigner). Entries are written as given (the caller keeps them ascending).
QByteArray encodeRelayLevelListBody(const RelayLevelList& list);
/// Parses a verified body; nullopt when malformed: wrong size or kind, a count above `total` or kMaxLevels, indices
/// not ascending or ≥ total, chunkBytes 0 or above kMaxRelayChunkBytes, payloadBytes 0 or above kMaxTransferSize.
std::optional<RelayLevelList> decodeRelayLevelListBody(QByteArrayView body);

/// The chunks of a payload of `payloadBytes` cut into `chunkBytes`: ceil(payloadBytes / chunkBytes). chunkBytes ≥ 1.
[[nodiscard]] std::uint32_t relayChunkCount(std::uint32_t payloadBytes, std::uint32_t chunkBytes);
/// The exact size of chunk `chunk` (< relayChunkCount()).
[[nodiscard]] std::uint32_t relayChunkSize(std::uint32_t payloadBytes, std::uint32_t chunkBytes, std::uint32_t chunk);

/// `SC_<sid>_LEVELS`, the stream; `sc.<sid>.level.>`, its subjects; `sc.<sid>.level.<index>.<chunk>`, one chunk.
std::string relayLevelStream(const QString& sessionId);
std::string relayLevelSubjects(const QString& sessionId);
std::string relayLevelChunkSubject(const QString& sessionId, std::uint8_t index, std::uint32_t chunk);

}  // namespace sc::session
