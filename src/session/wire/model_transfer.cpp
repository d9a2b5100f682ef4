#include "session/wire/model_transfer.h"

#include <openssl/sha.h>

#include <algorithm>
#include <cassert>
#include <utility>

namespace sc::session {

QByteArray sha256(QByteArrayView bytes) {
  // OpenSSL's SHA-256 (its assembly, SHA extensions where the CPU has them): the same digest as
  // QCryptographicHash, about 10× faster on a 100k-vertex level (docs/security.md, "Hostile host").
  QByteArray digest(SHA256_DIGEST_LENGTH, Qt::Uninitialized);
  SHA256(reinterpret_cast<const unsigned char*>(bytes.data()), static_cast<std::size_t>(bytes.size()),
         reinterpret_cast<unsigned char*>(digest.data()));
  return digest;
}

bool checksumMatches(QByteArrayView payload, QByteArrayView expected) {
  return expected.size() == kChecksumSize && QByteArrayView(sha256(payload)) == expected;
}

ModelSender::ModelSender(std::uint32_t transferId, TransferKind kind, std::uint32_t vertexCount, QByteArray payload,
                         std::uint32_t chunkBytes)
    : ModelSender(transferId, kind, vertexCount, payload, sha256(payload), chunkBytes) {}

ModelSender::ModelSender(std::uint32_t transferId, TransferKind kind, std::uint32_t vertexCount, QByteArray payload,
                         QByteArray payloadSha256, std::uint32_t chunkBytes)
    : m_payload(std::move(payload)), m_chunkBytes(chunkBytes) {
  assert(!m_payload.isEmpty() && static_cast<std::uint64_t>(m_payload.size()) <= kMaxTransferSize);
  assert(transferId >= 1 && vertexCount >= 1 && chunkBytes >= 1 && chunkBytes <= kMaxChunkBytes);
  assert(payloadSha256.size() == kChecksumSize);
  m_begin =
      ModelBegin{transferId, kind, vertexCount, static_cast<std::uint32_t>(m_payload.size()), std::move(payloadSha256)};
}

std::optional<ModelChunk> ModelSender::nextChunk() {
  if (finished()) return std::nullopt;
  const std::uint32_t size = std::min<std::uint32_t>(m_chunkBytes, m_begin.totalSize - m_offset);
  ModelChunk chunk{m_begin.transferId, m_offset, m_begin.totalSize, m_payload.sliced(m_offset, size)};
  m_offset += size;
  return chunk;
}

void ModelReceiver::begin(const ModelBegin& begin) {
  m_begin = begin;
  m_bytes = QByteArray();  // frees the replaced transfer's bytes
  m_complete = false;
}

ModelReceiver::Status ModelReceiver::add(const ModelChunk& chunk) { return append(chunk, true); }

ModelReceiver::Status ModelReceiver::addUnchecked(const ModelChunk& chunk) { return append(chunk, false); }

ModelReceiver::Status ModelReceiver::append(const ModelChunk& chunk, bool verify) {
  if (!m_begin || m_complete || chunk.transferId != m_begin->transferId) return Status::UnknownTransfer;
  if (chunk.offset != static_cast<std::uint32_t>(m_bytes.size()) || chunk.totalSize != m_begin->totalSize ||
      std::uint64_t{chunk.offset} + static_cast<std::uint64_t>(chunk.bytes.size()) > m_begin->totalSize) {
    abandon();
    return Status::OutOfOrder;
  }
  // Grow geometrically but never past totalSize (QByteArray's own growth could reserve up to twice the payload).
  const qsizetype needed = m_bytes.size() + chunk.bytes.size();
  if (needed > m_bytes.capacity()) {
    m_bytes.reserve(std::min<qsizetype>(m_begin->totalSize, std::max<qsizetype>(needed, 2 * m_bytes.capacity())));
  }
  m_bytes.append(chunk.bytes);
  if (static_cast<std::uint32_t>(m_bytes.size()) < m_begin->totalSize) return Status::InProgress;
  if (verify && !checksumMatches(m_bytes, m_begin->sha256)) {
    abandon();
    return Status::BadChecksum;
  }
  m_complete = true;
  return Status::Complete;
}

QByteArray ModelReceiver::take() {
  if (!m_complete) return {};
  QByteArray out = std::move(m_bytes);
  m_bytes = QByteArray();
  m_complete = false;
  m_begin.reset();
  return out;
}

void ModelReceiver::abandon() {
  m_begin.reset();
  m_bytes = QByteArray();
  m_complete = false;
}

const char* toString(ModelReceiver::Status status) {
  switch (status) {
    case ModelReceiver::Status::InProgress:
      return "in-progress";
    case ModelReceiver::Status::Complete:
      return "complete";
    case ModelReceiver::Status::UnknownTransfer:
      return "unknown-transfer";
    case ModelReceiver::Status::OutOfOrder:
      return "out-of-order";
    case ModelReceiver::Status::BadChecksum:
      return "bad-checksum";
  }
  return "?";
}

}  // namespace sc::session
