#pragma once
// Relay messages (issue 18): what the host publishes through a NATS broker for viewers (docs/protocol.md, "Relay
// through NATS"). New formats, apart from the TCP/UDP wire format (wire_format.h); they never travel on those.
// Every message is signed with the host's TLS identity key (ECDSA P-256, SHA-256) so that a broker, or a viewer
// with publish rights it should not have, cannot forge the shape: viewers pin the certificate's fingerprint.
//
//  offset size field         meaning (all integers big-endian)
//  ------ ---- ------------- -------------------------------------------------------------------------------------
//     0    2   magic         0x5343 ("SC")
//     2    1   version       kRelayVersion (1)
//     3    1   kind          RelayKind: 1 Frame (subject sc.<sid>.z and KV key `keyframe`), 2 Facts (KV `session`),
//                            3 Stats (viewer → host, sc.<sid>.stats.<viewer>; unsigned, no trailer)
//  Frame (kind 1): the exact Keyframe form, no quantisation (a TCP broker does not lose parts of a message):
//     4    4   frame         frame number (serial-number arithmetic, as on UDP)
//     8    8   stamp         host's steady clock (µs) when the input that produced the frame arrived; viewers on
//                            the same machine read one-way latency from it, others only differences
//    16    2   rowCount      m, 1..kMaxRows
//    18  24m   Z             m rows × (x, y, z) f64, row-major, finite
//  Facts (kind 2): the session's facts and the certificate whose key signs every message
//     4    2   rowCount      m, 1..kMaxRows
//     6    4   vertexCount   full-resolution vertex count, ≥ 1
//    10    2   certSize      c, 1..kMaxRelayCertificateBytes
//    12    c   certificate   the host's X.509 certificate, DER (its SHA-256 is the fingerprint viewers pin)
//  Stats (kind 3, exactly kRelayStatsSize = 92 bytes, no signature: advisory figures, anyone with the viewer
//  credential may send them):
//     4    8   viewer        random u64 chosen by the viewer at start
//    12    8   applied       frames applied since start
//    20    8   lost          frame numbers skipped
//    28    8   badSignature  frames dropped as not the host's
//    36    8   dropped       frames dropped while waiting (pending limit)
//    44    8   latencyP50    ms, f64, finite, 0..1e6 (last 10 s; meaningful on the host's machine only)
//    52    8   latencyP99    ms, idem
//    60    8   concealed     frames predicted (watch --concealment extrapolate; 0 with hold-last)
//    68    8   distortions   reference frames measured (0: no level, nothing measured)
//    76    8   distortionMean  % of the rest bounding-box diagonal, f64, finite, 0..1e6 (relay_display.h)
//    84    8   distortionMax   idem
//  Trailer (Frame and Facts):
//   end−1−s s  signature     ECDSA P-256 / SHA-256 (DER) over "SC-relay1" ‖ u8 |sid| ‖ sid ‖ bytes[0, end−1−s)
//   end−1   1  sigSize       s, 1..kMaxRelaySignatureBytes (the last byte: read first)
//
// Sizes: a frame of m = 100 rows is 18 + 2,400 + 1 + ≤ 72 ≈ 2.49 kB. The session id in the signed bytes binds a
// message to its session: a frame replayed into another session fails verification.
// Check order on receipt: length and kind (Malformed), signature (BadSignature), then fields (Malformed).

#include <Eigen/Core>
#include <QtCore/QByteArray>
#include <QtCore/QByteArrayView>
#include <QtCore/QString>

#include <cstdint>
#include <memory>
#include <optional>

namespace sc::session {

inline constexpr std::uint8_t kRelayVersion = 1;
inline constexpr int kMaxRelayCertificateBytes = 4096;
inline constexpr int kMaxRelaySignatureBytes = 72;  ///< DER ECDSA P-256 signature, at most
inline constexpr int kRelayFrameHeaderSize = 18;
inline constexpr int kMaxSessionIdBytes = 32;

/// Levels (4): the signed level list, KV key `levels` (relay_level_list.h).
enum class RelayKind : std::uint8_t { Frame = 1, Facts = 2, Stats = 3, Levels = 4 };
inline constexpr int kRelayStatsSize = 92;

/// Why a relay message was dropped (None = accepted); `Count` sizes counter arrays.
enum class RelayError { None, Malformed, BadSignature, Count };

/// One frame as published: the exact coefficients.
struct RelayFrame {
  std::uint32_t frame = 0;
  std::uint64_t stampMicros = 0;  ///< host steady clock, µs
  Eigen::MatrixXd Z;              ///< m by 3
};

/// The session's facts (KV key `session`).
struct RelayFacts {
  int rowCount = 0;
  std::uint32_t vertexCount = 0;
  QByteArray certificateDer;  ///< the host's certificate; SHA-256 of it = the fingerprint viewers pin
};

/// A viewer's figures sent back to the host (kind 3).
struct RelayStats {
  std::uint64_t viewer = 0;
  std::uint64_t applied = 0;
  std::uint64_t lost = 0;
  std::uint64_t badSignature = 0;
  std::uint64_t dropped = 0;
  double latencyP50Ms = 0;
  double latencyP99Ms = 0;
  std::uint64_t concealed = 0;    ///< frames predicted (Extrapolate)
  std::uint64_t distortions = 0;  ///< reference frames measured
  double distortionMeanPct = 0;   ///< over those, % of the diagonal
  double distortionMaxPct = 0;
};

/// The 92-byte Stats message (latencies and distortions clamped to [0, 1e6], non-finite sent as 0).
QByteArray encodeRelayStats(const RelayStats& stats);
/// nullopt unless exactly kRelayStatsSize bytes of kind Stats with finite latencies and distortions in [0, 1e6].
std::optional<RelayStats> decodeRelayStats(QByteArrayView message);

/// True for 1..kMaxSessionIdBytes characters of [A-Za-z0-9_-] (safe in a NATS subject and a KV bucket name).
bool isValidSessionId(const QString& sessionId);

/// Signs relay messages with the host's private key. Not thread-safe (one per publisher).
class RelaySigner {
 public:
  /// @param[in] privateKeyDer  the host's ECDSA private key, DER (QSslKey::toDer()); invalid() when unreadable.
  RelaySigner(QByteArrayView privateKeyDer, const QString& sessionId);
  ~RelaySigner();
  RelaySigner(const RelaySigner&) = delete;
  RelaySigner& operator=(const RelaySigner&) = delete;

  [[nodiscard]] bool valid() const { return m_key != nullptr; }
  /// The signed message: `body` ‖ signature ‖ sigSize. Empty when the key is invalid. Cost: one ECDSA sign (≈ 25 µs).
  [[nodiscard]] QByteArray sign(QByteArrayView body) const;

 private:
  struct Key;
  std::unique_ptr<Key> m_key;
  QByteArray m_context;  ///< "SC-relay1" ‖ |sid| ‖ sid
};

/// Verifies relay messages against one certificate's public key. Not thread-safe.
class RelayVerifier {
 public:
  /// @param[in] certificateDer  the host's certificate (DER); invalid() when unreadable or without an EC key.
  RelayVerifier(QByteArrayView certificateDer, const QString& sessionId);
  ~RelayVerifier();
  RelayVerifier(const RelayVerifier&) = delete;
  RelayVerifier& operator=(const RelayVerifier&) = delete;

  [[nodiscard]] bool valid() const { return m_key != nullptr; }
  /// The signed body of `message` (without the trailer) when its signature verifies; nullopt otherwise, with
  /// `error` Malformed (no well-formed trailer) or BadSignature. Cost: one ECDSA verify (≈ 55 µs).
  [[nodiscard]] std::optional<QByteArrayView> verify(QByteArrayView message, RelayError* error = nullptr) const;

 private:
  struct Key;
  std::unique_ptr<Key> m_key;
  QByteArray m_context;
};

/// The unsigned body of a Frame message. Non-finite entries are sent as 0. Cost: O(m).
QByteArray encodeRelayFrameBody(const RelayFrame& frame);
/// The unsigned body of a Facts message.
QByteArray encodeRelayFactsBody(const RelayFacts& facts);

/// The kind of a message (byte 3) when magic and version match; nullopt otherwise. Reads no further.
std::optional<RelayKind> relayKind(QByteArrayView message);
/// Parses a verified Frame body (RelayVerifier::verify's result); nullopt when malformed (also a non-finite value).
std::optional<RelayFrame> decodeRelayFrameBody(QByteArrayView body);
/// Parses a Facts body. Facts are read before any key is known: the caller checks the certificate against its pin,
/// then verifies the whole message with a verifier built from that certificate.
std::optional<RelayFacts> decodeRelayFactsBody(QByteArrayView body);
/// The body of a message without its trailer (no verification); nullopt when the trailer is malformed.
std::optional<QByteArrayView> relayBody(QByteArrayView message);

/// SHA-256 of a certificate's DER bytes (what users pin; equals TlsIdentity::fingerprint()).
QByteArray relayCertificateFingerprint(QByteArrayView certificateDer);

}  // namespace sc::session
