#include "session/wire/coefficient_codec.h"

#include <QtCore/QtEndian>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <utility>

namespace sc::session {
namespace {

constexpr int kMinExponent = -127;
constexpr int kMaxExponent = 127;
constexpr double kMaxQuantised = 32767.0;

/// Rows carried by part j, protected first, then k ≥ p with (k − p) mod P == j. Same rule on both ends.
std::vector<int> partRows(const DatagramHeader& header) {
  std::vector<int> rows;
  rows.reserve(static_cast<std::size_t>(header.protectedRows + interleavedRowCount(header)));
  for (int k = 0; k < header.protectedRows; ++k) rows.push_back(k);
  for (int k = header.protectedRows + header.partIndex; k < header.rowCount; k += header.partCount) rows.push_back(k);
  return rows;
}

/// Offset of the 16-bit sequence in the header (wire_format.h), read before authentication to extend it.
constexpr qsizetype kSequenceOffset = 6;

double finiteOrZero(double v) { return std::isfinite(v) ? v : 0.0; }

std::int16_t quantise(double v, int exponent) {
  const double q = std::nearbyint(std::ldexp(finiteOrZero(v), -exponent));
  return static_cast<std::int16_t>(std::clamp(q, -kMaxQuantised, kMaxQuantised));
}

}  // namespace

const char* toString(DecodeError error) {
  switch (error) {
    case DecodeError::None:
      return "none";
    case DecodeError::Truncated:
      return "truncated";
    case DecodeError::BadTag:
      return "bad-tag";
    case DecodeError::BadMagic:
      return "bad-magic";
    case DecodeError::BadVersion:
      return "bad-version";
    case DecodeError::Malformed:
      return "malformed";
    case DecodeError::Replayed:
      return "replayed";
    case DecodeError::Stale:
      return "stale";
    case DecodeError::Count:
      break;
  }
  return "unknown";
}

int bandExponent(double maxAbs) {
  if (!(maxAbs > 0.0) || !std::isfinite(maxAbs)) return kMinExponent;
  int e = static_cast<int>(std::ceil(std::log2(maxAbs / kMaxQuantised)));
  // log2 rounding can be off by one at exact powers of two: fix up so that 2^e is the smallest sufficient step.
  if (maxAbs / std::ldexp(1.0, e) > kMaxQuantised) ++e;
  if (e > kMinExponent && maxAbs / std::ldexp(1.0, e - 1) <= kMaxQuantised) --e;
  return std::clamp(e, kMinExponent, kMaxExponent);
}

QByteArray datagramTag(const QByteArray& key, QByteArrayView bytes) {
  const DatagramTag tag = DatagramMac(key).tag({bytes});
  return QByteArray(tag.data(), kTagSize);
}

QByteArray sealCoefficientDatagram(const QByteArray& key, std::uint64_t sequence, QByteArrayView clear) {
  const qsizetype header = std::min<qsizetype>(clear.size(), kDatagramHeaderSize);
  QByteArray out = clear.first(header).toByteArray();
  DatagramCipher(key, DatagramDirection::HostToClient).seal(sequence, clear.first(header), clear.sliced(header), out);
  return out;
}

std::optional<QByteArray> openCoefficientDatagram(const QByteArray& key, std::uint64_t sequence,
                                                  QByteArrayView datagram) {
  if (datagram.size() < kDatagramMinSize) return std::nullopt;
  QByteArray payload;
  const QByteArrayView header = datagram.first(kDatagramHeaderSize);
  if (!DatagramCipher(key, DatagramDirection::HostToClient)
           .open(sequence, header, datagram.sliced(kDatagramHeaderSize), payload)) {
    return std::nullopt;
  }
  return header.toByteArray() + payload;
}

// === encoder

CoefficientEncoder::CoefficientEncoder(QByteArray key, std::uint16_t peerId, CodecOptions options)
    : m_cipher(key, DatagramDirection::HostToClient), m_peerId(peerId), m_options(options) {
  assert(!key.isEmpty() && "a datagram key is required");
  assert(m_options.bandRows >= 1 && m_options.bandRows <= 255 && "bandRows must be in 1..255");
  assert(m_options.partsPerFrame >= 1 && m_options.partsPerFrame <= kMaxParts && "partsPerFrame in 1..kMaxParts");
}

int CoefficientEncoder::partCount(int m) const {
  DatagramHeader header;
  header.rowCount = static_cast<std::uint16_t>(m);
  header.protectedRows = static_cast<std::uint8_t>(std::clamp(m_options.protectedRows, 0, std::min(m, 255)));
  header.bandRows = static_cast<std::uint8_t>(m_options.bandRows);
  for (int parts = m_options.partsPerFrame; parts < kMaxParts; ++parts) {
    header.partCount = static_cast<std::uint8_t>(parts);
    if (expectedDatagramSize(header) <= kMaxDatagramSize) return parts;  // part 0 is the largest
  }
  return kMaxParts;
}

std::vector<QByteArray> CoefficientEncoder::encodeFrame(std::uint32_t frame, const Eigen::MatrixXd& Z,
                                                        std::uint32_t timestamp) {
  assert(Z.cols() == 3 && Z.rows() >= 1 && Z.rows() <= kMaxRows && "Z must be m by 3, 1 <= m <= kMaxRows");
  const int m = static_cast<int>(Z.rows());
  DatagramHeader header;
  header.peerId = m_peerId;
  header.frame = frame;
  header.timestamp = timestamp;
  header.rowCount = static_cast<std::uint16_t>(m);
  header.protectedRows = static_cast<std::uint8_t>(std::clamp(m_options.protectedRows, 0, std::min(m, 255)));
  header.bandRows = static_cast<std::uint8_t>(m_options.bandRows);
  header.partCount = static_cast<std::uint8_t>(partCount(m));

  // === one power-of-two step per band, from the band's largest finite |value|
  std::vector<int> exponents(static_cast<std::size_t>(bandCount(header)));
  for (std::size_t b = 0; b < exponents.size(); ++b) {
    const int first = static_cast<int>(b) * header.bandRows;
    const int count = std::min<int>(header.bandRows, m - first);
    const double maxAbs = Z.middleRows(first, count).unaryExpr(&finiteOrZero).cwiseAbs().maxCoeff();
    exponents[b] = bandExponent(maxAbs);
  }

  std::vector<QByteArray> parts;
  parts.reserve(header.partCount);
  for (int j = 0; j < header.partCount; ++j) {
    header.partIndex = static_cast<std::uint8_t>(j);
    header.sequence = static_cast<std::uint16_t>(m_sequence);  // the low 16 bits go on the wire
    parts.push_back(encodePart(header, m_sequence++, Z, exponents));
  }
  return parts;
}

QByteArray CoefficientEncoder::encodePart(const DatagramHeader& header, std::uint64_t sequence,
                                          const Eigen::MatrixXd& Z, const std::vector<int>& exponents) {
  QByteArray out;
  out.reserve(expectedDatagramSize(header));
  encodeDatagramHeader(header, out);
  m_payload.resize(0);  // keeps its capacity
  for (int e : exponents) m_payload.append(static_cast<char>(static_cast<std::int8_t>(e)));
  for (int k : partRows(header)) {
    const int e = exponents[static_cast<std::size_t>(k / header.bandRows)];
    for (int c = 0; c < 3; ++c) appendInt16(m_payload, quantise(Z(k, c), e));
  }
  m_cipher.seal(sequence, out, m_payload, out);  // the header is the additional authenticated data
  assert(out.size() == expectedDatagramSize(header) && out.size() <= kMaxDatagramSize);
  return out;
}

// === decoder

CoefficientDecoder::CoefficientDecoder(QByteArray key, std::uint16_t peerId)
    : m_cipher(key, DatagramDirection::HostToClient), m_peerId(peerId) {}

DecodeError CoefficientDecoder::decode(QByteArrayView bytes, DecodedDatagram& out) {
  if (bytes.size() < kDatagramMinSize) return DecodeError::Truncated;
  const std::uint64_t sequence = m_window.extend(qFromBigEndian<std::uint16_t>(bytes.data() + kSequenceOffset));
  const QByteArrayView header = bytes.first(kDatagramHeaderSize);
  if (!m_cipher.open(sequence, header, bytes.sliced(kDatagramHeaderSize), m_payload)) return DecodeError::BadTag;
  m_clear.resize(0);  // keeps its capacity
  m_clear.append(header);
  m_clear.append(m_payload);
  if (const DecodeError error = parse(m_clear, out); error != DecodeError::None) return error;
  out.sequence = sequence;
  switch (m_window.check(sequence)) {
    case ReplayVerdict::Replayed:
      return DecodeError::Replayed;
    case ReplayVerdict::Stale:
      return DecodeError::Stale;
    case ReplayVerdict::Fresh:
      break;
  }
  m_window.accept(sequence);
  return DecodeError::None;
}

DecodeError CoefficientDecoder::parse(QByteArrayView body, DecodedDatagram& out) const {
  const std::optional<DatagramHeader> header = decodeDatagramHeader(body);
  if (!header) return DecodeError::Truncated;
  if (header->magic != kMagic) return DecodeError::BadMagic;
  if (header->version != kProtocolVersion) return DecodeError::BadVersion;
  if (!headerRangesValid(*header) || header->peerId != m_peerId) return DecodeError::Malformed;
  const qsizetype expected = expectedDatagramSize(*header) - kTagSize;
  if (body.size() < expected) return DecodeError::Truncated;
  if (body.size() > expected) return DecodeError::Malformed;

  out.header = *header;
  out.rows = partRows(*header);
  out.values.resize(static_cast<Eigen::Index>(out.rows.size()), 3);
  const char* exponents = body.data() + kDatagramHeaderSize;
  const char* values = exponents + bandCount(*header);
  for (std::size_t i = 0; i < out.rows.size(); ++i) {
    const int e = static_cast<std::int8_t>(exponents[out.rows[i] / header->bandRows]);
    for (int c = 0; c < 3; ++c) {
      const std::int16_t q = readInt16(values + (3 * static_cast<qsizetype>(i) + c) * kValueSize);
      out.values(static_cast<Eigen::Index>(i), c) = std::ldexp(static_cast<double>(q), e);
    }
  }
  return DecodeError::None;
}

}  // namespace sc::session
