#pragma once
// Chunked, checksummed model transfer over the control channel (docs/protocol.md, "Model transfer"): the host's
// ModelSender cuts a payload (an encoded spectral::ResolutionLevel) into ModelChunks on demand, so that the socket
// adapter can interleave them with other messages and feed them as the socket drains; the client's ModelReceiver
// reassembles them, reports progress and checks the SHA-256. Pure: no sockets, no threads of its own; the free
// functions (sha256, checksumMatches) are thread-safe, so the costly hashes can run on a worker thread: the host
// hashes a level once when it is built (LevelLibrary) and hands the digest to ModelSender; the client may take a
// payload unchecked (ModelReceiver::addUnchecked) and verify it off its network thread.

#include "session/wire/control_messages.h"

#include <QtCore/QByteArray>

#include <cstdint>
#include <optional>

namespace sc::session {

/// SHA-256 of `bytes` (kChecksumSize bytes). Thread-safe. Cost: O(size).
QByteArray sha256(QByteArrayView bytes);

/// True when `expected` is the SHA-256 of `payload` (e.g. a payload taken after ModelReceiver::addUnchecked()
/// returned Complete, checked against that transfer's ModelBegin::sha256). Thread-safe. Cost: O(payload).
bool checksumMatches(QByteArrayView payload, QByteArrayView expected);

/// Host side of one transfer. The payload is implicitly shared (QByteArray), not copied.
class ModelSender {
 public:
  /// @pre 1 ≤ payload.size() ≤ kMaxTransferSize, transferId ≥ 1, vertexCount ≥ 1, 1 ≤ chunkBytes ≤ kMaxChunkBytes.
  /// Cost: one SHA-256 over the payload (on the calling thread).
  ModelSender(std::uint32_t transferId, TransferKind kind, std::uint32_t vertexCount, QByteArray payload,
              std::uint32_t chunkBytes = kMaxChunkBytes);
  /// Same with the payload's SHA-256 computed beforehand (e.g. once per level on a worker thread): O(1).
  /// @pre as above, and payloadSha256 == sha256(payload) (not re-checked: a wrong digest makes the client drop the
  ///      transfer as BadChecksum).
  ModelSender(std::uint32_t transferId, TransferKind kind, std::uint32_t vertexCount, QByteArray payload,
              QByteArray payloadSha256, std::uint32_t chunkBytes = kMaxChunkBytes);

  /// The announcement to send first.
  const ModelBegin& begin() const { return m_begin; }
  /// The next chunk in order, std::nullopt once every byte was handed out. Cost: O(chunk) copy.
  std::optional<ModelChunk> nextChunk();
  bool finished() const { return m_offset >= static_cast<std::uint32_t>(m_payload.size()); }
  std::uint32_t sentBytes() const { return m_offset; }

 private:
  ModelBegin m_begin;
  QByteArray m_payload;
  std::uint32_t m_chunkBytes;
  std::uint32_t m_offset = 0;
};

/// Client side. One transfer at a time: a new ModelBegin abandons an unfinished one.
class ModelReceiver {
 public:
  enum class Status : std::uint8_t {
    InProgress,       ///< accepted, more to come
    Complete,         ///< last chunk accepted and the SHA-256 matches (addUnchecked: not checked): take() it
    UnknownTransfer,  ///< chunk of no transfer in progress (or of another id): ignored
    OutOfOrder,       ///< offset ≠ bytes received so far, or totalSize disagrees: transfer abandoned
    BadChecksum,      ///< complete but the SHA-256 differs: transfer abandoned (add() only)
  };

  /// Starts a transfer, freeing an unfinished one (memory for totalSize is reserved lazily, as chunks arrive, never
  /// trusted up front, and never more than totalSize: reservedBytes()).
  void begin(const ModelBegin& begin);
  /// Appends one chunk. Cost: O(chunk), plus one SHA-256 over the payload on the last chunk.
  Status add(const ModelChunk& chunk);
  /// Like add(), but the last chunk returns Complete WITHOUT the SHA-256 check (never BadChecksum): O(chunk). The
  /// caller must then check the taken payload itself, checksumMatches(payload, current()->sha256) (read current()
  /// before take()), typically on a worker thread, and drop it on a mismatch.
  Status addUnchecked(const ModelChunk& chunk);
  /// The payload of a Complete transfer (then the receiver is idle again: current() is reset).
  QByteArray take();

  bool active() const { return m_begin.has_value(); }
  /// The current (or last Complete) transfer's announcement.
  const std::optional<ModelBegin>& current() const { return m_begin; }
  std::uint32_t receivedBytes() const { return static_cast<std::uint32_t>(m_bytes.size()); }
  std::uint32_t totalBytes() const { return m_begin ? m_begin->totalSize : 0; }
  /// Bytes of memory held for the payload (its capacity): never more than totalBytes().
  std::uint64_t reservedBytes() const { return static_cast<std::uint64_t>(m_bytes.capacity()); }

 private:
  Status append(const ModelChunk& chunk, bool verify);
  void abandon();

  std::optional<ModelBegin> m_begin;
  QByteArray m_bytes;
  bool m_complete = false;
};

const char* toString(ModelReceiver::Status status);

}  // namespace sc::session
