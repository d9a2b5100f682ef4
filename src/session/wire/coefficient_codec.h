#pragma once
// Coefficient datagram codec: quantises one frame's m×3 displacement coefficients Z, splits it into datagrams
// encrypted and authenticated with AES-128-GCM (datagram_cipher.h; layout in wire_format.h), and decrypts and
// decodes them on the receiver. Pure: no sockets, no clock.

#include "session/wire/datagram_cipher.h"
#include "session/wire/datagram_mac.h"
#include "session/wire/replay_window.h"
#include "session/wire/wire_format.h"

#include <Eigen/Core>
#include <QtCore/QByteArray>
#include <QtCore/QByteArrayView>

#include <cstdint>
#include <optional>
#include <vector>

namespace sc::session {

/// How a frame is laid out on the wire. Defaults: m = 100 gives 2 datagrams of 378 bytes, 756 bytes per frame.
struct CodecOptions {
  int partsPerFrame = 2;   ///< P ≥ 1; raised automatically so that every datagram stays ≤ kMaxDatagramSize.
  int protectedRows = 10;  ///< p: rows 0..p−1 repeated in every datagram (clamped to m).
  int bandRows = 10;       ///< rows per quantisation band (one power-of-two step per band), 1..255.
};

/// Why a datagram was dropped. `None` means accepted. `Count` sizes per-reason counter arrays.
enum class DecodeError {
  None,
  Truncated,   ///< shorter than header + tag, or (authenticated) shorter than its header implies.
  BadTag,      ///< not authentic under this peer's key and the extended sequence (AEAD tag; also any truncation).
  BadMagic,    ///< authenticated but not a ShapeCast datagram.
  BadVersion,  ///< authenticated, other protocol version.
  Malformed,   ///< authenticated, inconsistent fields (type, ranges, too long, wrong peer).
  Replayed,    ///< sequence number already accepted (duplicate or replay).
  Stale,       ///< sequence number behind the replay window.
  Count,
};

/// Human-readable name of a DecodeError ("bad-tag", …).
const char* toString(DecodeError error);

/// One decoded datagram: which rows of which frame it carries, dequantised.
struct DecodedDatagram {
  DatagramHeader header;
  std::uint64_t sequence = 0;  ///< extended (64-bit) sequence number; its low 16 bits are header.sequence
  std::vector<int> rows;       ///< row indices k in [0, m), protected rows first.
  Eigen::MatrixXd values;      ///< rows.size() by 3, dequantised.
};

/// HMAC-SHA256(key, bytes) truncated to kTagSize bytes, on a one-off DatagramMac (for tests and tools; the codecs
/// keep one per peer). Cost: O(#bytes) plus one OpenSSL context.
QByteArray datagramTag(const QByteArray& key, QByteArrayView bytes);

/// A coefficient datagram from its clear form (22-byte header ‖ plaintext payload): the payload sealed under the
/// host → client key of `key` with nonce = direction ‖ `sequence` (the extended sequence; not on the wire, only its
/// low 16 bits are: authenticating it is what makes a datagram of an earlier 16-bit cycle fail when replayed in a
/// later one). For tests and tools (one-off cipher context). Cost: O(bytes) plus one key derivation.
QByteArray sealCoefficientDatagram(const QByteArray& key, std::uint64_t sequence, QByteArrayView clear);
/// The clear form of a datagram (header ‖ plaintext payload); std::nullopt when shorter than kDatagramMinSize or not
/// authentic under `key` at `sequence`. For tests and tools.
std::optional<QByteArray> openCoefficientDatagram(const QByteArray& key, std::uint64_t sequence,
                                                  QByteArrayView datagram);

/// Host side, one per client (per-client key and sequence). Not thread-safe.
class CoefficientEncoder {
 public:
  /// @param[in] key  per-client datagram key (from the welcome), non-empty.
  /// @param[in] peerId  the client's peer id, written into every datagram.
  CoefficientEncoder(QByteArray key, std::uint16_t peerId, CodecOptions options = {});

  /// Quantises Z and returns its P datagrams, each authenticated and ≤ kMaxDatagramSize bytes. Non-finite
  /// entries are sent as 0. Consumes P (64-bit, never wrapping) sequence numbers.
  /// @param[in] frame  frame number (the caller increments it per frame).
  /// @param[in] Z  m by 3 displacement coefficients, 1 ≤ m ≤ kMaxRows.
  /// @param[in] timestamp  the header's timestamp field (host clock, µs mod 2³²; wire_format.h).
  /// Cost: O(m) plus P AES-128-GCM seals over ≤ 1200 bytes.
  std::vector<QByteArray> encodeFrame(std::uint32_t frame, const Eigen::MatrixXd& Z, std::uint32_t timestamp = 0);

  /// Parts a frame of m rows is split into (≥ options.partsPerFrame when needed for the size limit).
  int partCount(int m) const;
  /// The extended sequence number of the next datagram (the wire carries its low 16 bits).
  std::uint64_t nextSequence() const { return m_sequence; }
  void setNextSequence(std::uint64_t sequence) { m_sequence = sequence; }

 private:
  QByteArray encodePart(const DatagramHeader& header, std::uint64_t sequence, const Eigen::MatrixXd& Z,
                        const std::vector<int>& exponents);

  DatagramCipher m_cipher;  ///< host → client
  QByteArray m_payload;     ///< scratch: one part's plaintext payload
  std::uint16_t m_peerId;
  CodecOptions m_options;
  std::uint64_t m_sequence = 0;
};

/// Client side: authenticates, parses and de-duplicates datagrams from the host. Not thread-safe.
/// Order of checks as in wire_format.h: the datagram is decrypted and its tag verified (nonce from the sequence
/// extended by the replay window, ReplayWindow::extend) before any other field is read; the replay window is updated
/// only for datagrams that pass every check.
class CoefficientDecoder {
 public:
  /// @param[in] key  this client's datagram key.
  /// @param[in] peerId  this client's peer id; datagrams addressed to another peer are Malformed.
  CoefficientDecoder(QByteArray key, std::uint16_t peerId);

  /// Decodes one datagram into `out` (left unspecified on failure). Never reads past `bytes`.
  /// Cost: one AES-128-GCM open of the datagram plus O(rows); no allocation once the scratch buffers grew.
  DecodeError decode(QByteArrayView bytes, DecodedDatagram& out);

  const ReplayWindow& replayWindow() const { return m_window; }

 private:
  DecodeError parse(QByteArrayView body, DecodedDatagram& out) const;

  DatagramCipher m_cipher;  ///< host → client
  QByteArray m_payload;     ///< scratch: the decrypted payload
  QByteArray m_clear;       ///< scratch: header ‖ decrypted payload, what parse() reads
  std::uint16_t m_peerId;
  ReplayWindow m_window;
};

/// Quantisation step of a band whose largest |value| is maxAbs: the smallest 2^e with maxAbs / 2^e ≤ 32767, so
/// the rounding error is ≤ 2^e / 2 ≤ maxAbs / 32767. Returns e in [−127, 127].
int bandExponent(double maxAbs);

}  // namespace sc::session
