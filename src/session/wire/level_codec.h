#pragma once
// Compressed level payloads (docs/protocol.md, "Model transfer"; issue 17): what a ModelBegin/ModelChunk transfer
// carries is the canonical level payload (spectral::encodeResolutionLevel(), level format 2) squeezed losslessly by
// well-kept codecs: meshoptimizer's vertex codec for the rest positions X̂', its index codec for the faces F', zstd
// for P and the scales, and zstd for K's int16 entries after a prediction along the mesh. The decoder rebuilds the
// canonical bytes exactly, so the SHA-256 of a transfer (ModelBegin::sha256) is taken over the DECODED payload.
//
// Layout of a compressed payload (version 1, little-endian, no padding; counts as in resolution_level.h):
//
//   offset  size  field
//   0       8     magic "SCLVZ\0\r\n"
//   8       4     u32 codec version (kLevelCodecVersion)
//   12      20    u32 n', f', n, m, z: the canonical payload's counts (its size follows from them)
//   32      4     u32 flags: bit 0 = faces as zstd of the raw i32 (the index codec would not have round-tripped them)
//   36      16    u32 byte size of each section, in order: positions, faces, tables, K
//   52      …     positions: meshopt_encodeVertexBuffer of X̂' (n' vertices of 24 bytes: the f64 xyz)
//   …       …     faces: meshopt_encodeIndexBuffer of F' (3f' u32), or zstd of the raw 12f' bytes (flag bit 0)
//   …       …     tables: one zstd frame of the CSR offsets, P's columns and weights, K's scales and the canonical
//                 checksum, exactly as in the canonical payload (4(n'+1) + 12z + 4m + 8 bytes)
//   …       …     K: one zstd frame of 2n'm bytes: K's rows visited in breadth-first order over F' (restarting at
//                 the lowest unvisited vertex), each row minus its prediction (int16 wrap-around): the rounded
//                 mean of the parallelograms Q_a + Q_b − Q_c over its faces (v, a, b) whose corners a, b and a
//                 vertex c across (a, b) are visited (at most 16 faces looked at per vertex), else the rounded mean
//                 of its visited neighbours' rows, else 0; zig-zag coded, stored column by column as a plane of low
//                 bytes then a plane of high bytes.
//
// Decoding is bounded: the counts give the canonical size, checked against the caller's limit BEFORE anything is
// allocated; every zstd frame must declare (ZSTD_getFrameContentSize) exactly its section's decoded size; the
// sections must fill the payload exactly. Any codec error is refused with a message; garbage that decodes is caught
// by the SHA-256 over the decoded bytes and then by spectral::decodeResolutionLevel().

#include <QtCore/QByteArray>
#include <QtCore/QByteArrayView>
#include <QtCore/QString>

#include <cstdint>
#include <optional>

namespace sc::session {

inline constexpr std::uint32_t kLevelCodecVersion = 1;

/// Compresses a canonical level payload (spectral::encodeResolutionLevel() bytes). Empty when `canonical` is not a
/// well-formed level-format-2 header with consistent sizes (a programmer error on the host). zstd at `level`.
/// Cost: O(n'·m) for the prediction plus the codecs (1.4 s for the 100k dragon's full level at level 9 on the
/// development machine, decompression 0.24 s; docs/benchmarks.md).
[[nodiscard]] QByteArray compressLevelPayload(QByteArrayView canonical, int zstdLevel = 9);

/// The canonical payload's size declared by a compressed payload's header, or nullopt when the header is short,
/// not ours or of another codec version. O(1).
[[nodiscard]] std::optional<std::uint64_t> declaredLevelPayloadSize(QByteArrayView compressed);

/// Result of decompressLevelPayload(): the canonical bytes, or an error.
struct LevelDecompression {
  QByteArray payload;  ///< canonical level payload (its SHA-256 is the transfer's), empty on error
  QString error;       ///< non-empty when refused
  [[nodiscard]] bool ok() const { return error.isEmpty(); }
};

/// Rebuilds the canonical payload. Refuses (error set, nothing big allocated) a header whose declared canonical size
/// exceeds `maxPayloadBytes`, sections that do not fill the buffer exactly, a zstd frame whose declared content size
/// is not its section's, and any codec error. Never throws on malformed input (std::bad_alloc aside).
/// Cost: O(canonical size) plus the codecs.
[[nodiscard]] LevelDecompression decompressLevelPayload(QByteArrayView compressed, std::uint64_t maxPayloadBytes);

}  // namespace sc::session
