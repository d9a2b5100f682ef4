#pragma once
// THE wire format of ShapeCast (style.md item 10): every byte that crosses the network is described here.
//
// Conventions
//   - Fixed-width integers only. All multi-byte fields are BIG-endian (network order), converted once, here, by
//     encodeDatagramHeader()/decodeDatagramHeader() through qToBigEndian/qFromBigEndian.
//   - Every decoder checks the length before reading a field; malformed input is dropped and counted by the caller
//     (style.md item 6), never asserted on.
//
// ==================================================================================================================
// Coefficient datagram (UDP, host -> client), MessageType::CoefficientFrame
// ==================================================================================================================
// One frame's m×3 displacement coefficients Z are sent as P datagrams ("parts"). Rows 0..p−1 (the protected low
// frequencies) are repeated in every part; the other rows are interleaved: part j carries rows k ≥ p with
// (k − p) mod P == j, in ascending order. Values are int16 with one power-of-two step per band of `bandRows` rows.
//
//  offset size field            meaning
//  ------ ---- ---------------- ---------------------------------------------------------------------------------
//     0    2   magic            0x5343 ("SC")
//     2    1   version          kProtocolVersion
//     3    1   type             MessageType (CoefficientFrame)
//     4    2   peerId           receiving peer's id (selects the per-client key on the host side)
//     6    2   sequence         per-peer datagram sequence number, +1 per datagram, wraps at 65535 -> 0
//     8    4   frame            frame number, +1 per frame (serial-number arithmetic, wraps)
//    12    1   partIndex        j in [0, partCount)
//    13    1   partCount        P in [1, kMaxParts]
//    14    2   rowCount         m in [1, kMaxRows]: rows in the whole frame
//    16    1   protectedRows    p in [0, m]
//    17    1   bandRows         rows per band, ≥ 1; band b covers rows [b·bandRows, (b+1)·bandRows)
//  ------ ---- ---------------- --------------------------------------------- 18 bytes: kDatagramHeaderSize
//    18    B   bandExponent[B]  int8 e_b per band, B = ceil(m / bandRows); value = q · 2^e_b
//   18+B  6·p  protected        p rows × (x, y, z) int16
//   ...   6·r  interleaved      r = number of k in [p, m) with (k − p) mod P == j, rows × (x, y, z) int16
//   end−T  T   tag              HMAC-SHA256(perClientKey, all preceding bytes), truncated to T = kTagSize bytes
//
// Sizes for m = 100, p = 10, bandRows = 10, P = 2: 18 + 10 + 60 + 45·6 + 16 = 374 bytes per part, 748 per frame.
//
// Receiver order of checks: length ≥ kDatagramMinSize (Truncated), tag (BadTag), magic (BadMagic), version
// (BadVersion), type and field ranges (Malformed), exact length (Truncated/Malformed), then the replay window
// (Replayed/Stale), which is updated only after everything else succeeded (RFC 6347 §4.1.2.6).
//
// ==================================================================================================================
// control messages: see the session issue (TCP; hello, welcome, model transfer, lock protocol, ...) — to be added
// ==================================================================================================================

#include <QtCore/QByteArray>
#include <QtCore/QByteArrayView>

#include <cstdint>
#include <optional>

namespace sc::session {

inline constexpr std::uint16_t kMagic = 0x5343;  ///< "SC", first two bytes of every datagram.
inline constexpr std::uint8_t kProtocolVersion = 1;

/// Message types, explicit values. Datagram types use values below 0x40, control (TCP) types from 0x40 on.
enum class MessageType : std::uint8_t {
  CoefficientFrame = 0x01,
  Count,  ///< one past the last datagram type; keep last among datagram types.
};
inline constexpr std::uint8_t kMessageTypeMask = 0x7f;  ///< the high bit is reserved (must be 0).

// === size table
inline constexpr int kDatagramHeaderSize = 18;  ///< fixed header, offsets 0..17.
inline constexpr int kTagSize = 16;             ///< truncated HMAC-SHA256 tag.
inline constexpr int kDatagramMinSize = kDatagramHeaderSize + kTagSize;
inline constexpr int kMaxDatagramSize = 1200;  ///< QUIC's floor; every datagram we send is at most this.
inline constexpr int kValueSize = 2;           ///< one int16 coefficient.
inline constexpr int kRowSize = 3 * kValueSize;
inline constexpr int kMaxParts = 64;
inline constexpr int kMaxRows = 4096;

/// The fixed header of a coefficient datagram, host byte order.
struct DatagramHeader {
  std::uint16_t magic = kMagic;
  std::uint8_t version = kProtocolVersion;
  MessageType type = MessageType::CoefficientFrame;
  std::uint16_t peerId = 0;
  std::uint16_t sequence = 0;
  std::uint32_t frame = 0;
  std::uint8_t partIndex = 0;
  std::uint8_t partCount = 1;
  std::uint16_t rowCount = 0;
  std::uint8_t protectedRows = 0;
  std::uint8_t bandRows = 1;
};

/// Appends the 18 header bytes, big-endian, to `out`. Cost: O(1).
void encodeDatagramHeader(const DatagramHeader& header, QByteArray& out);

/// Reads the 18 header bytes at the start of `bytes`; std::nullopt when fewer than 18 bytes. Checks nothing else
/// (magic, version and ranges are the caller's, see validateDatagramHeader()). Cost: O(1).
std::optional<DatagramHeader> decodeDatagramHeader(QByteArrayView bytes);

/// Number of bands B = ceil(m / bandRows); 0 when bandRows is 0.
int bandCount(const DatagramHeader& header);

/// Number of interleaved (unprotected) rows in part j of a frame: #{k in [p, m) : (k − p) mod P == j}.
int interleavedRowCount(const DatagramHeader& header);

/// Exact datagram size implied by a header (header, exponents, rows, tag). Header must be range-valid.
int expectedDatagramSize(const DatagramHeader& header);

/// True when the range fields are consistent: 1 ≤ P ≤ kMaxParts, j < P, 1 ≤ m ≤ kMaxRows, p ≤ m, bandRows ≥ 1,
/// type is a known datagram type.
bool headerRangesValid(const DatagramHeader& header);

/// Big-endian helpers for the payload (int16 values), used by the codec. `at` must leave room: callers check.
void appendInt16(QByteArray& out, std::int16_t value);
std::int16_t readInt16(const char* at);

}  // namespace sc::session
